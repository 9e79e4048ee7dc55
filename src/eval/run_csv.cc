#include "memloop/run_csv.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>
#include <vector>

#include "eval/csv_line.h"
#include "memloop/errors.h"

namespace memloop {
namespace {

template <typename T>
std::string Join(const std::vector<T>& values) {
  std::ostringstream text;
  for (size_t i = 0; i < values.size(); ++i) text << (i ? ";" : "") << values[i];
  return text.str();
}

std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

constexpr const char* kHeader =
    "image,name,location_id,matched_image,matched_location,matched_images,hypothesis_id,"
    "hypothesis_value,hypothesis_images,hypothesis_eligible,inliers,virtual_place,rehearsal_merged,"
    "features,words,"
    "iteration_ms,signature_ms,rehearsal_ms,likelihood_ms,filter_ms,selection_ms,retrieval_ms,"
    "transfer_ms,checkpoint_ms,stm_size,wm_size,ltm_size,dictionary_size,retrieved,transferred,"
    "ltm_wait_ms,cpu_ms,ltm_read_ms,timestamp,session,features_skipped,appearance_match,"
    "appearance_z,rel_tx,rel_ty,rel_tz,rel_qx,rel_qy,rel_qz,rel_qw,rel_metric,pose_reason,"
    "matched_robot,hypothesis_robot,time_decided";

// A name in quotes, or nothing for none.
std::string QuotedName(const std::string& name) { return name.empty() ? "" : Quoted(name); }

// Seconds to the microsecond (TUM's resolution; EuRoC's nanoseconds are beyond a double's
// precision at today's epoch anyway); empty when unknown.
std::string FormatTimestamp(double timestamp) {
  if (!HasTimestamp(timestamp)) return "";
  char text[64];
  std::snprintf(text, sizeof(text), "%.6f", timestamp);
  return text;
}

// The epipolar inliers of the hypothesis (verify.min_inliers) or, when they were not checked,
// of the accepted loop closure's two views (camera.fx..cy); -1 when neither was.
int Inliers(const Result& result) {
  const LoopGeometry& geometry = result.loop_closure_geometry;
  if (result.hypothesis_inliers >= 0 || geometry.correspondences < 8) {
    return result.hypothesis_inliers;
  }
  return static_cast<int>(geometry.inliers.size());
}

// rel_tx..rel_qw, rel_metric, pose_reason: the query camera in the match camera's frame, or, for
// a loop closure without a pose, why; empty for an image without a loop closure.
std::string RelativePose(const Result& result) {
  if (!result.HasLoopClosure()) return ",,,,,,,,";
  const LoopGeometry& g = result.loop_closure_geometry;
  if (!g.has_pose) return ",,,,,,,," + Quoted(g.pose_problem);
  char text[256];
  std::snprintf(text, sizeof(text), "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,", g.translation[0],
                g.translation[1], g.translation[2], g.quaternion[0], g.quaternion[1],
                g.quaternion[2], g.quaternion[3], g.translation_metric ? 1 : 0);
  return text;
}

}  // namespace

RunCsvWriter::RunCsvWriter(const std::string& path) : path_(path) { Create(); }

void RunCsvWriter::CheckCanCreate(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error)) throw InputError(path, "is a folder, not a results file");
  if (fs::exists(path, error)) {
    if (access(path.c_str(), W_OK) != 0) {
      throw InputError(path, std::string("cannot write the results file: ") + std::strerror(errno));
    }
    return;
  }
  const fs::path folder =
      fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(folder, error)) {
    throw InputError(
        path, "cannot write the results file: the folder " + folder.string() + " does not exist");
  }
  if (access(folder.c_str(), W_OK) != 0) {
    throw InputError(path, "cannot write the results file: the folder " + folder.string() +
                               " is not writable (" + std::strerror(errno) + ")");
  }
}

void RunCsvWriter::Create() {
  out_.open(path_);
  if (!out_) throw InputError(path_, "cannot write the results file");
  out_ << kHeader << '\n';
  out_.flush();
  if (!out_) throw InputError(path_, "writing the results failed (disk full?)");
}

namespace {

// A resumed CSV's header and rows of images up to `keep_through`; nullopt when there is no file.
struct KeptRows {
  std::string text;
  long long rows = 0;
  ImageIndex last_image = kNoImage;
  long long rows_after = 0;  // rows of later images, dropped
};

std::optional<KeptRows> ReadKeptRows(const std::string& path, ImageIndex keep_through) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::string line;
  if (!std::getline(in, line) || line != kHeader) {
    throw InputError(path,
                     "not a results CSV of this memloop: cannot continue it (give another "
                     "--out, or remove the file)");
  }
  KeptRows kept{line + '\n'};
  // Rows are in image order; a row cut by a crash (no end of line) goes too.
  while (std::getline(in, line) && !in.eof()) {
    char* end = nullptr;
    const long image = std::strtol(line.c_str(), &end, 10);
    if (end == line.c_str() || *end != ',') break;
    if (image > keep_through) {
      ++kept.rows_after;
      continue;
    }
    if (kept.rows_after > 0) break;  // not in image order: not kept
    kept.text += line + '\n';
    ++kept.rows;
    kept.last_image = static_cast<ImageIndex>(image);
  }
  return kept;
}

}  // namespace

void RunCsvWriter::CheckContinues(const std::string& path, ImageIndex keep_through,
                                  long long images, long long max_rows_after) {
  const std::optional<KeptRows> kept = ReadKeptRows(path, keep_through);
  if (kept && kept->rows == images && kept->rows_after > max_rows_after) {
    throw InputError(path, "holds " + std::to_string(kept->rows_after) + " rows after image " +
                               std::to_string(keep_through) +
                               ", the map's last: more than a run killed after its last "
                               "checkpoint leaves (at most " +
                               std::to_string(max_rows_after) +
                               "), so another run's results; give this map's own CSV, or "
                               "another --out");
  }
  if (!kept || kept->rows == images) return;
  if (kept->rows < images && (kept->rows == 0 || kept->last_image < keep_through)) {
    throw InputError(path, "holds results up to image " +
                               (kept->rows == 0 ? "none" : std::to_string(kept->last_image)) +
                               " but the map holds " + std::to_string(images) +
                               " images up to image " + std::to_string(keep_through) +
                               ": the rows between are lost; run again without --resume, or "
                               "give this map's own CSV");
  }
  throw InputError(path, "is not this map's results: " + std::to_string(kept->rows) +
                             " rows up to image " + std::to_string(keep_through) +
                             ", where the map holds " + std::to_string(images) +
                             " images; give this map's own CSV, or another --out");
}

RunCsvWriter::RunCsvWriter(const std::string& path, ImageIndex keep_through) : path_(path) {
  const std::optional<KeptRows> kept = ReadKeptRows(path, keep_through);
  if (!kept) {  // nothing to continue: a new CSV
    Create();
    return;
  }
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << kept->text;
    out.close();
    if (!out) throw InputError(temporary, "writing the results failed (disk full?)");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw InputError(path, std::string("cannot replace the results file: ") + std::strerror(errno));
  }
  out_.open(path, std::ios::app);
  if (!out_) throw InputError(path, "cannot write the results file");
}

void RunCsvWriter::Write(const std::string& image_name, const Result& result) {
  const StageTimes& t = result.times;
  // The row is formatted first and written at once: a kill leaves whole rows only.
  std::ostringstream row;
  row << result.image_index << ',' << Quoted(image_name) << ',' << result.location_id << ',';
  if (result.HasLoopClosure()) {
    row << (result.loop_closure_images.empty() ? kNoImage : result.loop_closure_images.front())
        << ',' << result.loop_closure_id << ',' << Join(result.loop_closure_images);
  } else {
    row << ",,";
  }
  row << ',' << result.hypothesis_id << ',' << result.hypothesis_value << ','
      << Join(result.hypothesis_images) << ',' << result.hypothesis_eligible << ','
      << Inliers(result) << ',' << result.virtual_place_probability << ','
      << result.rehearsal_merged_id << ',' << result.feature_count << ',' << result.word_count
      << ',' << t.total_ms << ',' << t.signature_ms << ',' << t.rehearsal_ms << ','
      << t.likelihood_ms << ',' << t.filter_ms << ',' << t.selection_ms << ',' << t.retrieval_ms
      << ',' << t.transfer_ms << ',' << t.checkpoint_ms << ',' << result.stm_size << ','
      << result.wm_size << ',' << result.ltm_size << ',' << result.dictionary_size << ','
      << Join(result.retrieved_ids) << ',' << Join(result.transferred_ids) << ',' << t.ltm_wait_ms
      << ',' << t.cpu_ms << ',' << t.ltm_read_ms << ',' << FormatTimestamp(result.timestamp) << ','
      << result.session << ',' << result.features_skipped << ',';
  if (result.appearance_match_id != kNoLocation) {
    row << result.appearance_match_id << ',' << result.appearance_match_z;
  } else {
    row << ',';
  }
  row << ',' << RelativePose(result) << ','
      << QuotedName(result.HasLoopClosure() ? result.loop_closure_robot : "") << ','
      << QuotedName(result.hypothesis_robot) << ',' << result.time_decided << '\n';
  const std::string text = row.str();
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  out_.flush();
  if (!out_) throw InputError(path_, "writing the results failed (disk full?)");
}

void RunCsvWriter::Close() {
  if (!out_.is_open()) return;
  out_.close();
  if (!out_) throw InputError(path_, "writing the results failed (disk full?)");
}

namespace {

constexpr double kMaxRunImages = 10'000'000;  // images of one run, at most
constexpr double kMaxId = 2'147'483'647;

std::string Format(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace

// Splits one CSV line; fields may be quoted ("a,b" and "" for a quote inside).
std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

std::vector<RunRow> ReadRunCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path, "is empty: not a memloop run CSV");
  std::map<std::string, size_t> column;
  const std::vector<std::string> header = SplitCsvLine(line);
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* required :
       {"image", "name", "location_id", "matched_images", "hypothesis_id", "hypothesis_value",
        "hypothesis_images", "iteration_ms", "wm_size", "dictionary_size"}) {
    if (!column.count(required)) {
      throw InputError(path, std::string("not a memloop run CSV (no column '") + required + "')");
    }
  }
  std::vector<RunRow> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    if (fields.size() != header.size()) {
      throw InputError(path, "line " + std::to_string(number) + " has " +
                                 std::to_string(fields.size()) + " fields, the header " +
                                 std::to_string(header.size()));
    }
    const auto text = [&](const char* name) { return fields[column.at(name)]; };
    const auto fail = [&](const char* name, const std::string& problem) {
      return InputError(path, "line " + std::to_string(number) + ": " + name + " '" + text(name) +
                                  "' " + problem);
    };
    const auto real_of = [&](const char* name, double min, double max) {
      const std::string& field = text(name);
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(value)) {
        throw fail(name, "is not a number");
      }
      if (value < min || value > max) {
        throw fail(name, "is out of range [" + Format(min) + ", " + Format(max) + "]");
      }
      return value;
    };
    const auto whole = [&](const char* name, const std::string& field, double max) {
      char* end = nullptr;
      errno = 0;
      const long long value = std::strtoll(field.c_str(), &end, 10);
      if (field.empty() || end != field.c_str() + field.size() || errno == ERANGE) {
        throw fail(name, "is not a whole number");
      }
      if (value < 0 || value > max) throw fail(name, "is out of range [0, " + Format(max) + "]");
      return value;
    };
    const auto integer_of = [&](const char* name, double max) {
      return whole(name, text(name), max);
    };
    const auto list_of = [&](const char* name) {
      std::vector<ImageIndex> values;
      std::stringstream list(text(name));
      for (std::string item; std::getline(list, item, ';');) {
        values.push_back(static_cast<ImageIndex>(whole(name, item, kMaxRunImages - 1)));
      }
      return values;
    };
    RunRow row;
    row.image = static_cast<ImageIndex>(integer_of("image", kMaxRunImages - 1));
    if (!rows.empty() && row.image <= rows.back().image) {
      throw fail("image", "does not follow image " + std::to_string(rows.back().image) +
                              " (a run's images are in increasing order, each once)");
    }
    row.name = text("name");
    row.location_id = static_cast<LocationId>(integer_of("location_id", kMaxId));
    row.matched_images = list_of("matched_images");
    row.hypothesis_id = static_cast<LocationId>(integer_of("hypothesis_id", kMaxId));
    row.hypothesis_value = real_of("hypothesis_value", 0, 1);
    row.hypothesis_images = list_of("hypothesis_images");
    // Runs before the column: every hypothesis counted as T_loop's to decide.
    row.hypothesis_eligible =
        !column.count("hypothesis_eligible") || integer_of("hypothesis_eligible", 1) == 1;
    // A fleet's map: images of another robot's place are that robot's.
    if (column.count("matched_robot")) row.matched_robot = text("matched_robot");
    if (column.count("hypothesis_robot")) row.hypothesis_robot = text("hypothesis_robot");
    for (const auto& [name, images, robot] :
         {std::tuple{"matched_images", &row.matched_images, &row.matched_robot},
          std::tuple{"hypothesis_images", &row.hypothesis_images, &row.hypothesis_robot}}) {
      if (!robot->empty()) continue;
      for (ImageIndex image : *images) {
        if (image >= row.image) throw fail(name, "names an image not seen before this one");
      }
    }
    row.iteration_ms = real_of("iteration_ms", 0, 1e12);
    for (const char* stage : {"likelihood_ms", "filter_ms", "selection_ms"}) {
      if (column.count(stage)) row.wm_stages_ms += real_of(stage, 0, 1e12);
    }
    if (column.count("cpu_ms")) row.cpu_ms = real_of("cpu_ms", 0, 1e12);
    row.wm_size = static_cast<int>(integer_of("wm_size", kMaxId));
    if (column.count("ltm_size")) row.ltm_size = static_cast<int>(integer_of("ltm_size", kMaxId));
    row.dictionary_size = static_cast<int>(integer_of("dictionary_size", kMaxId));
    if (column.count("timestamp") && !text("timestamp").empty()) {
      row.timestamp = real_of("timestamp", -1e12, 1e12);
    }
    if (column.count("session")) row.session = static_cast<int>(integer_of("session", kMaxId));
    if (column.count("time_decided")) row.time_decided = text("time_decided");
    rows.push_back(std::move(row));
  }
  // Images are indexed by their position in the input, skipped (unreadable) ones included: a run
  // that names an image far beyond its rows is not memloop's (and would size the ground truth).
  // A later session's rows start after the earlier sessions' images.
  if (!rows.empty() &&
      rows.back().image - rows.front().image >= 2 * static_cast<ImageIndex>(rows.size()) + 16) {
    throw InputError(path, "image " + std::to_string(rows.back().image) +
                               " (last line) is beyond "
                               "what a run of " +
                               std::to_string(rows.size()) +
                               " rows can name (more images skipped than processed)");
  }
  if (rows.empty()) throw InputError(path, "holds no image row");
  return rows;
}

}  // namespace memloop
