// memloop report: a page that agrees with eval, draws in a browser, and shows what was matched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "cli_helpers.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/image_sequence.h"
#include "memloop/run_csv.h"
#include "route_images_test.h"

namespace memloop {
namespace {

class ReportTest : public testing::RouteImagesTest<ReportTest> {
 protected:
  // The page as headless Chromium (installed by `make test`) leaves it once loaded, and its log.
  std::string BrowserDom(const std::string& page, std::string* log) {
    const std::string browser =
        "timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic "
        "--no-first-run --disable-background-networking --disable-component-update "
        "--disable-sync --hide-scrollbars --virtual-time-budget=5000 --window-size=1200,900 "
        "--user-data-dir=" +
        dir_.File("profile");
    const std::string dom = dir_.File("dom.html");
    EXPECT_EQ(std::system((browser + " --dump-dom file://" + page + " > " + dom + " 2> " +
                           dir_.File("chromium.log"))
                              .c_str()),
              0);
    *log = ReadFile(dir_.File("chromium.log"));
    return ReadFile(dom);
  }
  static bool HasBrowser() { return std::system("command -v chromium > /dev/null 2>&1") == 0; }
};

// Self-contained: nothing is loaded from elsewhere (xmlns URIs are names, not loads).
void ExpectSelfContained(const std::string& html) {
  for (const char* load : {"src=\"http", "href=\"http", "src='http", "href='http", "<link"}) {
    EXPECT_EQ(html.find(load), std::string::npos) << load;
  }
  EXPECT_EQ(std::count(html.begin(), html.end(), '\0'), 0);
}

// Every figure draws, the page logs no error, every thumbnail decodes, and a screenshot is kept in
// build/test-artifacts/report.png. The first screen (1200x900) shows the summary, with the run's
// own figure first, and the first image pair; the misses are listed with their true match; every
// point of the ground-truth figure that links leads to a row of its pair. Without ground truth,
// the run's own figures draw.
TEST_F(ReportTest, RendersInABrowserWithEachLoopClosuresImages) {
  if (!HasBrowser()) GTEST_SKIP() << "chromium is not installed (make test installs it)";
  const std::string csv = dir_.File("run.csv");
  const std::string map = dir_.File("map.db");
  ASSERT_EQ(Memloop("run " + Images() +
                    " --set memory.time_limit_ms=0 --set memory.stm_size=12 "
                    "--db " +
                    map + " --out " + csv)
                .exit_code,
            0);
  const std::vector<RunRow> rows = ReadRunCsv(csv);
  std::vector<std::string> names;
  for (const RunRow& row : rows) names.push_back(row.name);
  const GroundTruth truth = GroundTruth::Load(folder_->File("ground_truth_pairs.csv"),
                                              GroundTruthFormat::kAuto, names, rows.size());
  int loop_closures = 0, misses = 0;
  for (const RunRow& row : rows) {
    loop_closures += !row.matched_images.empty();
    misses += row.matched_images.empty() && truth.HasEarlierMatch(row.image);
  }
  ASSERT_GT(loop_closures, 20);
  ASSERT_GT(misses, 0);
  const std::string page = dir_.File("report.html");
  const Outcome report =
      Memloop("report " + csv + " " + folder_->path().string() + " --map " + map +
              " --time-limit-ms 700 --images " + Images() + " --max-views 20 --out " + page);
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = ReadFile(page);
  ExpectSelfContained(html);
  EXPECT_TRUE(Contains(html, std::to_string(loop_closures) + " loop closures accepted, " +
                                 std::to_string(misses) + (misses == 1 ? " image" : " images") +
                                 " with a true match missed"));
  EXPECT_TRUE(Contains(html, "; 20 with their images"));
  EXPECT_TRUE(Contains(html, "memory.stm_size=12"));  // the map's parameters, the changed one named
  EXPECT_TRUE(Contains(html, "<td>700 ms</td>"));
  EXPECT_LT(html.find("the run accepted, at its T<sub>loop</sub>"), html.find("best threshold"));
  // The first row is the first miss (no false positive here), by its file name and true match.
  const size_t first_row = html.find("<tr id=\"pair-");
  ASSERT_NE(first_row, std::string::npos);
  const std::string row = html.substr(first_row, html.find("</td>", first_row) - first_row);
  EXPECT_TRUE(Contains(row, "class=\"missed\"")) << row;
  EXPECT_TRUE(Contains(row, ".png</b> <span class=\"verdict\">missed</span>: highest hypothesis"))
      << row;
  EXPECT_TRUE(Contains(row, "; true match ")) << row;
  // Each link of the figure has its row.
  int links = 0;
  for (size_t at = html.find("<a href=\"#pair-"); at != std::string::npos;
       at = html.find("<a href=\"#pair-", at + 1), ++links) {
    const size_t id = at + 10;
    const std::string target = html.substr(id, html.find('"', id) - id);
    EXPECT_TRUE(Contains(html, "<tr id=\"" + target + "\"")) << target;
  }
  EXPECT_EQ(links, loop_closures + misses);

  std::string log;
  const std::string dom = BrowserDom(page, &log);
  const size_t body = dom.find("<body");
  const std::string body_tag = dom.substr(body, dom.find('>', body) - body);
  EXPECT_TRUE(Contains(body_tag, "data-rendered=\"4\"")) << body_tag;
  int thumbnails = 0;
  for (size_t at = html.find("<img "); at != std::string::npos; at = html.find("<img ", at + 1)) {
    ++thumbnails;
  }
  EXPECT_GE(thumbnails, 40);
  EXPECT_TRUE(Contains(body_tag, "data-images=\"" + std::to_string(thumbnails) + "\"")) << body_tag;
  EXPECT_TRUE(Contains(body_tag, "data-errors=\"\"")) << body_tag;
  const size_t bottom_at = body_tag.find("data-first-pair-bottom=\"");
  ASSERT_NE(bottom_at, std::string::npos) << body_tag;
  const int first_pair_bottom = std::stoi(body_tag.substr(bottom_at + 24));
  EXPECT_GT(first_pair_bottom, 0) << body_tag;
  EXPECT_LE(first_pair_bottom, 900) << "the first image pair is below the first screen";
  EXPECT_FALSE(Contains(log, "Uncaught")) << log;
  const std::string artifacts = std::string(MEMLOOP_BUILD_DIR) + "/test-artifacts";
  std::filesystem::create_directories(artifacts);
  std::system(("timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
               "--user-data-dir=" +
               dir_.File("profile") + " --window-size=1200,900 --screenshot=" + artifacts +
               "/report.png file://" + page + " > /dev/null 2>&1")
                  .c_str());
  EXPECT_TRUE(std::filesystem::exists(artifacts + "/report.png"));

  const std::string alone = dir_.File("alone.html");
  ASSERT_EQ(Memloop("report " + csv + " --images " + Images() + " --out " + alone).exit_code, 0);
  ExpectSelfContained(ReadFile(alone));
  EXPECT_TRUE(Contains(ReadFile(alone), "no ground truth given"));
  const std::string alone_dom = BrowserDom(alone, &log);
  EXPECT_TRUE(Contains(alone_dom, "data-rendered=\"2\"")) << alone_dom.substr(0, 600);
  EXPECT_TRUE(Contains(alone_dom,
                       "data-images=\"" + std::to_string(2 * std::min(loop_closures, 200)) + "\""))
      << alone_dom.substr(0, 600);
}

std::vector<unsigned char> FromBase64(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> bytes;
  unsigned value = 0;
  int bits = 0;
  for (char c : text) {
    const size_t digit = alphabet.find(c);
    if (digit == std::string::npos) break;  // '=' padding
    value = value << 6 | static_cast<unsigned>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes.push_back(static_cast<unsigned char>(value >> bits & 0xff));
    }
  }
  return bytes;
}

// A run on a video sampled with --rate numbers its images 0, 1, 2, ... while they are the video's
// frames 1, 3, 5, ...: each thumbnail must show the frame its alt text names (the run's own), not
// the video's frame at the run's index.
TEST_F(ReportTest, ThumbnailsOfASampledVideoShowTheFramesTheRunRead) {
  const std::string video = dir_.File("route.avi");
  std::vector<cv::Mat> frames;
  {
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                           cv::Size(320, 240));
    ASSERT_TRUE(writer.isOpened());
    for (const auto& name : ListFolder(Images())) {
      frames.push_back(cv::imread(Images() + "/" + name));
      writer.write(frames.back());
    }
  }
  const std::string csv = dir_.File("run.csv");
  ASSERT_EQ(
      Memloop("run " + video + " --rate 5 --set memory.time_limit_ms=0 --out " + csv).exit_code, 0);
  const std::string page = dir_.File("report.html");
  const Outcome report =
      Memloop("report " + csv + " --images " + video + " --max-views 6 --out " + page);
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = ReadFile(page);
  int checked = 0;
  for (size_t at = html.find("<img alt=\"image "); at != std::string::npos;
       at = html.find("<img alt=\"image ", at + 1)) {
    const size_t frame_at = html.find("(frame ", at) + 7;
    const int frame = std::stoi(html.substr(frame_at));
    const size_t data = html.find("base64,", at) + 7;
    const std::vector<unsigned char> jpeg =
        FromBase64(html.substr(data, html.find('"', data) - data));
    const cv::Mat shown = cv::imdecode(jpeg, cv::IMREAD_COLOR);
    ASSERT_FALSE(shown.empty());
    cv::Mat expected;
    cv::resize(frames.at(frame - 1), expected, shown.size(), 0, 0, cv::INTER_AREA);
    EXPECT_LT(cv::norm(shown, expected, cv::NORM_L1) / shown.total() / 3, 12.0)
        << "frame " << frame;
    ++checked;
  }
  EXPECT_EQ(checked, 12);  // 6 loop closures, two images each (no ground truth: no true match)
}

// --images must be the run's sequence: a folder without the run's files is named.
TEST_F(ReportTest, ImagesThatAreNotTheRunsAreRefused) {
  const std::string csv = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + csv).exit_code, 0);
  std::filesystem::create_directories(dir_.File("other"));
  const Outcome refused = Memloop("report " + csv + " --images " + dir_.File("other") + " --out " +
                                  dir_.File("r.html"));
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_TRUE(Contains(refused.output, dir_.File("other") + ": has no readable image '"))
      << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("r.html")));
  const Outcome no_truth = Memloop("report " + csv + " --ignored-as-true");
  EXPECT_EQ(no_truth.exit_code, 2) << no_truth.output;
  EXPECT_TRUE(Contains(no_truth.output, "--ignored-as-true")) << no_truth.output;
}

}  // namespace
}  // namespace memloop
