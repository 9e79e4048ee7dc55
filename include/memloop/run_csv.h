#pragma once

#include <fstream>
#include <string>
#include <vector>

#include "memloop/result.h"

namespace memloop {

// The per-image results of a run, one row per processed image, for plotting and `memloop eval`.
// Columns: see docs/cli.md. Times are in milliseconds.
class RunCsvWriter {
 public:
  // Throws InputError when `path` cannot be written.
  explicit RunCsvWriter(const std::string& path);
  // Throws InputError, naming `path`, when a new CSV could not be written there (a folder, a
  // missing or read-only folder, a read-only file); creates nothing.
  static void CheckCanCreate(const std::string& path);
  // A resumed run's CSV: keeps the header and the rows of images up to `keep_through` (those the
  // map's checkpoint holds), drops later ones (they are processed again), and appends. A missing
  // file starts a new CSV. Throws InputError when the file is not a run CSV of this memloop.
  RunCsvWriter(const std::string& path, ImageIndex keep_through);
  // Before a resume touches anything: throws InputError, naming `path`, when its rows up to
  // `keep_through` are not those of a map that holds `images` images up to it (the CSV of
  // another run, or one whose last rows were lost, e.g. on a full disk), or when it holds more
  // than `max_rows_after` rows after `keep_through`: more than a run killed after the map's last
  // checkpoint leaves, so another, longer run's results. A missing file passes.
  static void CheckContinues(const std::string& path, ImageIndex keep_through, long long images,
                             long long max_rows_after);
  // Writes and flushes one row, so that a killed run leaves whole rows. Throws InputError when
  // the write fails (a full disk).
  void Write(const std::string& image_name, const Result& result);
  // Closes the file, checking that its last bytes were written.
  void Close();

 private:
  void Create();  // a new file with the header line

  std::string path_;
  std::ofstream out_;
};

// One row of a run's CSV, as `memloop eval` needs it.
struct RunRow {
  ImageIndex image = kNoImage;
  std::string name;
  LocationId location_id = kNoLocation;
  std::vector<ImageIndex> matched_images;  // empty: no loop closure accepted
  LocationId hypothesis_id = kNoLocation;
  double hypothesis_value = 0;
  std::vector<ImageIndex> hypothesis_images;
  bool hypothesis_eligible = true;  // Result::hypothesis_eligible
  double iteration_ms = 0;
  // likelihood + filter + selection: the stages that grow with WM (0 in CSVs without them).
  double wm_stages_ms = 0;
  double cpu_ms = -1;  // the detector's thread's CPU time (StageTimes::cpu_ms); -1 without it
  int wm_size = 0;
  int ltm_size = 0;  // 0 in CSVs without it
  int dictionary_size = 0;
  double timestamp = kNoTimestamp;  // seconds; unknown in CSVs without it
  int session = 0;
  std::string time_decided;  // Result::time_decided; empty in CSVs without it
  // A fleet's map: the robot whose images matched_images (hypothesis_images) are when the place is
  // another robot's; empty for the run's own places (and in CSVs without the columns).
  std::string matched_robot;
  std::string hypothesis_robot;
};

// Reads a CSV written by RunCsvWriter. Throws InputError naming the file and, for a malformed
// row, its line: unreadable, not a memloop run (a column missing), a field that is not a number,
// not a whole number where one is needed, out of range (negative, non-finite, a hypothesis outside
// [0, 1]), images not in increasing order, a match that is not an earlier image, or an image
// index far beyond the run's rows.
std::vector<RunRow> ReadRunCsv(const std::string& path);

}  // namespace memloop
