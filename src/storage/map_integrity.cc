#include "storage/map_integrity.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#include "memloop/errors.h"

namespace memloop {
namespace {

// SQLite's quick_check in one line: empty when it finds nothing wrong, else the first problem and
// how many there are (its report is one line per problem, up to 100, after a header line).
std::string QuickCheckProblems(SqliteConnection& connection) {
  SqliteStatement check(connection, "PRAGMA quick_check");
  std::vector<std::string> problems;
  try {
    while (check.Step()) {
      std::istringstream lines(check.Text(0));
      for (std::string line; std::getline(lines, line);) {
        if (!line.empty() && line != "ok" && line.rfind("*** in database", 0) != 0)
          problems.push_back(line);
      }
    }
  } catch (const DatabaseError&) {  // the check itself stopped on a damaged page
    if (problems.empty()) problems.push_back(sqlite3_errmsg(connection.handle()));
  }
  if (problems.empty()) return "";
  if (problems.size() == 1) return problems.front();
  const std::string count =
      problems.size() >= 100 ? "100 or more" : std::to_string(problems.size());
  return count + " problems found by SQLite's quick_check, the first: " + problems.front();
}

// What identifies a map file's content without reading it: the file's and its log's device,
// inode, size and modification time (nanoseconds). Any later write changes one of them.
struct FileStamp {
  std::vector<long long> fields;
  double newest_write_s = 0;  // the newest modification time, seconds since the epoch
  bool operator<(const FileStamp& other) const { return fields < other.fields; }
};
FileStamp StampOf(const std::string& path) {
  FileStamp stamp;
  for (const std::string& file : {path, path + "-wal"}) {
    struct stat info {};
    if (stat(file.c_str(), &info) != 0) {
      stamp.fields.insert(stamp.fields.end(), {-1, -1, -1, -1, -1});
      continue;
    }
    stamp.fields.insert(
        stamp.fields.end(),
        {static_cast<long long>(info.st_dev), static_cast<long long>(info.st_ino),
         static_cast<long long>(info.st_size), static_cast<long long>(info.st_mtim.tv_sec),
         static_cast<long long>(info.st_mtim.tv_nsec)});
    stamp.newest_write_s =
        std::max(stamp.newest_write_s, static_cast<double>(info.st_mtim.tv_sec) +
                                           1e-9 * static_cast<double>(info.st_mtim.tv_nsec));
  }
  return stamp;
}

double NowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// The files this process found intact, as they were then: opening one again, unchanged, does not
// read it whole again. `memloop run --resume` opens a map three times (its parameters, its
// progress, the run): a map of a million LTM locations (63 GB, bench/pad_map.py) took 17-19
// minutes per check.
struct CheckedFiles {
  std::mutex mutex;
  std::set<FileStamp> intact;
  long long checks = 0;
};
CheckedFiles& Checked() {
  static CheckedFiles checked;
  return checked;
}

// MapIntegrityProblems: QuickCheckProblems, once per unchanged file in this process. A file is
// remembered only if it was last written over a second before its check began: a later write then
// has a later time, however coarse the file system's clock (a write in the same tick as the stamp
// could keep it).
}  // namespace

std::string MapIntegrityProblems(SqliteConnection& connection, const std::string& path) {
  const FileStamp stamp = StampOf(path);
  CheckedFiles& checked = Checked();
  {
    std::lock_guard<std::mutex> lock(checked.mutex);
    if (checked.intact.count(stamp) > 0) return "";
  }
  const double started_s = NowS();
  const std::string problems = QuickCheckProblems(connection);
  std::lock_guard<std::mutex> lock(checked.mutex);
  ++checked.checks;
  if (problems.empty() && stamp.newest_write_s < started_s - 1.0) checked.intact.insert(stamp);
  return problems;
}

long long MapIntegrityChecksRun() {
  std::lock_guard<std::mutex> lock(Checked().mutex);
  return Checked().checks;
}

}  // namespace memloop
