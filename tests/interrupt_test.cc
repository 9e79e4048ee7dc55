// Stopping the memloop tool: SIGINT and SIGTERM end the run after the current image with the map
// closed, the CSV on a whole line and in agreement with the map, and exit 128 + signal; kill -9
// of a run without --db leaves a temporary map that the next run removes.
//
// The CSV goes to a FIFO with a one-page buffer that the test reads: the run cannot get more than
// a few rows ahead of the test, so the signal always falls mid-run, however slow the machine.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "cli_helpers.h"
#include "memloop/image_sequence.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

struct PipedRun {
  std::string csv;  // everything the run wrote to its CSV
  int status = 0;   // waitpid status
  std::string log;  // stdout and stderr
};

// Starts the tool with its CSV going to a FIFO read here; once `rows` rows are read, sends
// `signal` to it, then reads on until it has exited.
PipedRun RunAndSignal(const testing::TempDir& dir, std::vector<std::string> arguments, int rows,
                      int signal, const std::string& temporary_folder = "") {
  const std::string fifo = dir.File("csv.fifo");
  fs::remove(fifo);
  EXPECT_EQ(mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  // Opened before the run starts, so the buffer is small before any row is written.
  const int fd = open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  EXPECT_GE(fd, 0) << std::strerror(errno);
  fcntl(fd, F_SETPIPE_SZ, 4096);
  arguments.insert(arguments.end(), {"--out", fifo});
  PipedRun run;
  const std::string log = dir.File("log");
  const pid_t child = Start(arguments, log, temporary_folder);
  bool signalled = false;
  bool exited = false;
  char buffer[512];
  while (true) {
    const ssize_t got = read(fd, buffer, sizeof(buffer));
    if (got > 0) {
      run.csv.append(buffer, got);
      if (!signalled && std::count(run.csv.begin(), run.csv.end(), '\n') > rows) {
        kill(child, signal);
        signalled = true;
      }
      continue;
    }
    if (exited) break;  // all read after the exit
    exited = waitpid(child, &run.status, WNOHANG) == child;
    if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  close(fd);
  run.log = ReadFile(log);
  EXPECT_TRUE(signalled) << "the run ended before " << rows << " rows:\n" << run.log;
  return run;
}

// The image index of each data row.
std::vector<int> RowImages(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<int> images;
  while (std::getline(in, line)) images.push_back(std::stoi(line));
  return images;
}

int Count(const std::string& text, const std::string& part) {
  int count = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

class InterruptTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SyntheticRoute(testing::ShortRoute()).Write(dir_.path().string());
    images_ = dir_.File("images");
  }

  testing::TempDir dir_;
  std::string images_;
};

TEST_F(InterruptTest, SigintFinishesTheImageClosesTheMapAndResumes) {
  ASSERT_EQ(Memloop("run " + images_ + " --set memory.time_limit_ms=0 memory.max_wm_locations=30" +
                    " --out " + dir_.File("whole.csv"))
                .exit_code,
            0);
  const int total = CsvRows(dir_.File("whole.csv"));
  const std::string map = dir_.File("map.db");
  const PipedRun run = RunAndSignal(dir_,
                                    {"run", images_, "--db", map, "--set", "memory.time_limit_ms=0",
                                     "memory.max_wm_locations=30"},
                                    65, SIGINT);
  ASSERT_TRUE(WIFEXITED(run.status)) << run.log;
  EXPECT_EQ(WEXITSTATUS(run.status), 130) << run.log;
  ASSERT_FALSE(run.csv.empty());
  EXPECT_EQ(run.csv.back(), '\n') << "the CSV ends mid-line";
  const std::vector<int> images = RowImages(run.csv);
  ASSERT_GE(images.size(), 65u);
  ASSERT_LT(static_cast<int>(images.size()), total);
  const int last = images.back();
  EXPECT_TRUE(Contains(run.log, "interrupted by SIGINT after image " + std::to_string(last)))
      << run.log;
  // Loop closures were printed as they were found, one line each.
  EXPECT_GT(RowsWithLoopClosure(run.csv), 0);
  EXPECT_EQ(Count(run.log, ": loop closure with location"), RowsWithLoopClosure(run.csv))
      << run.log;
  // The map was closed: it holds every image of the CSV, and goes on to the uninterrupted result.
  EXPECT_FALSE(fs::exists(map + "-wal"));
  std::ofstream(dir_.File("run.csv")) << run.csv;
  const Outcome resumed =
      Memloop("run " + images_ + " --db " + map + " --resume --out " + dir_.File("run.csv"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Contains(resumed.output, "after image " + std::to_string(last) + " ("))
      << resumed.output;
  EXPECT_EQ(WithoutTimes(ReadFile(dir_.File("run.csv"))),
            WithoutTimes(ReadFile(dir_.File("whole.csv"))));
}

// A video input stops the same way (a camera is read through the same loop).
TEST_F(InterruptTest, SigintOnAVideo) {
  const std::string video = dir_.File("route.avi");
  {
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                           cv::Size(320, 240));
    ASSERT_TRUE(writer.isOpened());
    for (const std::string& name : ListFolder(images_)) {
      writer.write(cv::imread(images_ + "/" + name));
    }
  }
  const PipedRun run = RunAndSignal(dir_, {"run", video}, 40, SIGINT);
  ASSERT_TRUE(WIFEXITED(run.status)) << run.log;
  EXPECT_EQ(WEXITSTATUS(run.status), 130) << run.log;
  EXPECT_EQ(run.csv.back(), '\n');
  EXPECT_TRUE(Contains(
      run.log, "interrupted by SIGINT after image " + std::to_string(RowImages(run.csv).back())))
      << run.log;
}

TEST_F(InterruptTest, SigtermRemovesTheTemporaryMap) {
  const std::string temporary = dir_.File("tmp");
  fs::create_directory(temporary);
  const PipedRun run = RunAndSignal(dir_, {"run", images_}, 30, SIGTERM, temporary);
  ASSERT_TRUE(WIFEXITED(run.status)) << run.log;
  EXPECT_EQ(WEXITSTATUS(run.status), 143) << run.log;
  EXPECT_EQ(run.csv.back(), '\n');
  EXPECT_TRUE(Contains(
      run.log, "interrupted by SIGTERM after image " + std::to_string(RowImages(run.csv).back())))
      << run.log;
  EXPECT_TRUE(fs::is_empty(temporary));
}

TEST_F(InterruptTest, KilledRunsTemporaryMapIsRemovedByTheNextRun) {
  const std::string temporary = dir_.File("tmp");
  fs::create_directory(temporary);
  const PipedRun run = RunAndSignal(dir_, {"run", images_}, 30, SIGKILL, temporary);
  ASSERT_TRUE(WIFSIGNALED(run.status));
  EXPECT_FALSE(fs::is_empty(temporary)) << "kill -9 leaves the map: nothing can remove it then";
  // The map it left is readable as it is, and reading it (inspect) changes no byte, log included.
  std::string map;
  for (const auto& entry : fs::directory_iterator(temporary)) {
    if (entry.path().extension() == ".db") map = entry.path().string();
  }
  ASSERT_FALSE(map.empty());
  const std::string main_bytes = ReadFile(map);
  const std::string log_bytes = ReadFile(map + "-wal");
  const Outcome inspect = Memloop("inspect " + map + " --json");
  EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
  EXPECT_TRUE(Contains(inspect.output, "\"integrity\": \"ok\"")) << inspect.output;
  EXPECT_EQ(ReadFile(map), main_bytes);
  EXPECT_EQ(ReadFile(map + "-wal"), log_bytes);
  const pid_t next = Start({"params"}, dir_.File("params.log"), temporary);  // no map: kept
  int status = 0;
  waitpid(next, &status, 0);
  EXPECT_FALSE(fs::is_empty(temporary));
  const pid_t again = Start({"run", images_}, dir_.File("again.log"), temporary);
  waitpid(again, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << ReadFile(dir_.File("again.log"));
  EXPECT_TRUE(fs::is_empty(temporary));
}

}  // namespace
}  // namespace memloop
