#include "input/dataset_listing.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "memloop/errors.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

bool IsFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}
bool IsFolder(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

// Lines of a listing without their line ends ("\r\n" too), numbered from 1.
std::vector<std::pair<int, std::string>> ReadLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot be read");
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.emplace_back(number, line);
  }
  return lines;
}

bool IsBlankOrComment(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t");
  return first == std::string::npos || line[first] == '#';
}

[[noreturn]] void LineError(const fs::path& listing, int line, const std::string& problem) {
  throw InputError(listing.string(), "line " + std::to_string(line) + ": " + problem);
}

double ParseSeconds(const fs::path& listing, int line, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value)) {
    LineError(listing, line, "'" + text + "' is not a time stamp in seconds");
  }
  return value;
}

// Timestamps must not go back: a rate samples them in order, and a back-end orders poses by them.
void CheckTimeOrder(const fs::path& listing, const std::vector<int>& lines,
                    const std::vector<ListedImage>& images) {
  for (size_t i = 1; i < images.size(); ++i) {
    if (images[i].timestamp < images[i - 1].timestamp) {
      LineError(listing, lines[i],
                "time stamp before the previous line's (the listing must be in "
                "time order)");
    }
  }
  if (images.empty()) throw InputError(listing.string(), "the listing holds no image");
}

// A TUM RGB-D listing (rgb.txt, depth.txt): "# comment" lines, then "timestamp filename" with
// filename relative to the folder; each entry with its line number.
struct TumEntry {
  int line;
  double stamp;
  std::string name;
};

std::vector<TumEntry> ReadTumListing(const fs::path& listing) {
  std::vector<TumEntry> entries;
  for (const auto& [number, line] : ReadLines(listing)) {
    if (IsBlankOrComment(line)) continue;
    std::istringstream fields(line);
    std::string stamp, name, extra;
    if (!(fields >> stamp >> name) || (fields >> extra)) {
      LineError(listing, number, "expected 'timestamp filename', not '" + line + "'");
    }
    entries.push_back({number, ParseSeconds(listing, number, stamp), name});
  }
  return entries;
}

// TUM RGB-D's depth.txt, when there is one: each image takes the depth map nearest its time
// stamp within 0.02 s (the benchmark's associate.py), 5000 units per metre (its format).
void AddTumDepth(const fs::path& folder, DatasetListing& result) {
  const fs::path listing = folder / "depth.txt";
  if (!IsFile(listing)) return;
  std::vector<TumEntry> depths = ReadTumListing(listing);
  std::stable_sort(depths.begin(), depths.end(),
                   [](const TumEntry& a, const TumEntry& b) { return a.stamp < b.stamp; });
  std::vector<double> times;
  for (const TumEntry& depth : depths) times.push_back(depth.stamp);
  for (ListedImage& image : result.images) {
    const int nearest = NearestTime(times, image.timestamp, 0.02);
    if (nearest >= 0) image.depth_path = (folder / depths[nearest].name).string();
  }
  result.depth_units_per_metre = 5000;
}

DatasetListing ListTum(const fs::path& folder) {
  const fs::path listing = folder / "rgb.txt";
  if (!IsFile(listing)) throw InputError(folder.string(), "not a TUM folder (no rgb.txt)");
  DatasetListing result{InputFormat::kTum, {}, listing.string()};
  std::vector<int> lines;
  for (const TumEntry& entry : ReadTumListing(listing)) {
    result.images.push_back({entry.name, (folder / entry.name).string(), entry.stamp});
    lines.push_back(entry.line);
  }
  CheckTimeOrder(listing, lines, result.images);
  AddTumDepth(folder, result);
  return result;
}

// The EuRoC camera folder under `folder`: folder itself (cam0), cam0 (mav0), or mav0/cam0.
fs::path EurocCameraFolder(const fs::path& folder) {
  for (const fs::path& camera : {folder / "mav0" / "cam0", folder / "cam0", folder}) {
    if (IsFile(camera / "data.csv") && IsFolder(camera / "data")) return camera;
  }
  return {};
}

// EuRoC MAV: "#timestamp [ns],filename" then "1403636579763555584,1403636579763555584.png".
DatasetListing ListEuroc(const fs::path& folder) {
  const fs::path camera = EurocCameraFolder(folder);
  if (camera.empty()) {
    throw InputError(folder.string(), "not a EuRoC folder (no mav0/cam0/data.csv beside data/)");
  }
  const fs::path listing = camera / "data.csv";
  DatasetListing result{InputFormat::kEuroc, {}, listing.string()};
  std::vector<int> lines;
  for (const auto& [number, line] : ReadLines(listing)) {
    if (IsBlankOrComment(line)) continue;
    const size_t comma = line.find(',');
    std::string name = comma == std::string::npos ? "" : line.substr(comma + 1);
    name.erase(0, name.find_first_not_of(" \t"));
    const std::string stamp = line.substr(0, comma);
    char* end = nullptr;
    const long long nanoseconds = std::strtoll(stamp.c_str(), &end, 10);
    if (name.empty() || stamp.empty() || *end != '\0' || nanoseconds < 0) {
      LineError(listing, number, "expected 'timestamp in ns,filename', not '" + line + "'");
    }
    result.images.push_back(
        {name, (camera / "data" / name).string(), static_cast<double>(nanoseconds) * 1e-9});
    lines.push_back(number);
  }
  CheckTimeOrder(listing, lines, result.images);
  return result;
}

// "2011-09-26 13:02:25.964389445" (KITTI raw), in seconds since 1970 UTC.
double ParseDateTime(const fs::path& listing, int line, const std::string& text) {
  int year, month, day, hour, minute;
  double second;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%d %d:%d:%lf%c", &year, &month, &day, &hour, &minute,
                  &second, &tail) != 6 ||
      month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 || second < 0 ||
      second >= 61) {
    LineError(listing, line, "'" + text + "' is not a time 'YYYY-MM-DD HH:MM:SS.fraction'");
  }
  std::tm date{};
  date.tm_year = year - 1900;
  date.tm_mon = month - 1;
  date.tm_mday = day;
  date.tm_hour = hour;
  date.tm_min = minute;
  return static_cast<double>(timegm(&date)) + second;
}

// The KITTI images folder under `folder`: odometry's image_0 (left gray) or image_2 (left colour)
// beside times.txt; raw's image_00 or image_02 with data/ and timestamps.txt.
struct KittiLayout {
  fs::path images;
  fs::path times;
  bool raw = false;
};
KittiLayout FindKitti(const fs::path& folder) {
  if (IsFile(folder / "times.txt")) {
    for (const char* camera : {"image_0", "image_2"}) {
      if (IsFolder(folder / camera)) return {folder / camera, folder / "times.txt", false};
    }
  }
  for (const char* camera : {"image_00", "image_02"}) {
    if (IsFolder(folder / camera / "data") && IsFile(folder / camera / "timestamps.txt")) {
      return {folder / camera / "data", folder / camera / "timestamps.txt", true};
    }
  }
  return {};
}

DatasetListing ListKitti(const fs::path& folder) {
  const KittiLayout layout = FindKitti(folder);
  if (layout.images.empty()) {
    throw InputError(folder.string(),
                     "not a KITTI folder (no times.txt beside image_0/ or image_2/, nor "
                     "image_00/data/ with image_00/timestamps.txt)");
  }
  std::vector<double> times;
  std::vector<int> lines;
  for (const auto& [number, line] : ReadLines(layout.times)) {
    if (IsBlankOrComment(line)) continue;
    const size_t first = line.find_first_not_of(" \t");
    const std::string text = line.substr(first, line.find_last_not_of(" \t") + 1 - first);
    times.push_back(layout.raw ? ParseDateTime(layout.times, number, text)
                               : ParseSeconds(layout.times, number, text));
    lines.push_back(number);
  }
  const std::vector<std::string> names = ListFolder(layout.images.string());
  if (names.size() != times.size()) {
    throw InputError(layout.times.string(), std::to_string(times.size()) + " times for " +
                                                std::to_string(names.size()) + " images in " +
                                                layout.images.string() + " (one time per image)");
  }
  DatasetListing result{InputFormat::kKitti, {}, layout.times.string()};
  for (size_t i = 0; i < names.size(); ++i) {
    result.images.push_back({names[i], (layout.images / names[i]).string(), times[i]});
  }
  CheckTimeOrder(layout.times, lines, result.images);
  return result;
}

DatasetListing ListPlainFolder(const fs::path& folder) {
  DatasetListing result{InputFormat::kFolder, {}, ""};
  for (const std::string& name : ListFolder(folder.string())) {
    result.images.push_back({name, (folder / name).string(), kNoTimestamp});
  }
  if (result.images.empty()) throw InputError(folder.string(), "the folder holds no image");
  return result;
}

}  // namespace

InputFormat ParseInputFormat(const std::string& name) {
  for (InputFormat format : {InputFormat::kAuto, InputFormat::kFolder, InputFormat::kTum,
                             InputFormat::kEuroc, InputFormat::kKitti}) {
    if (name == InputFormatName(format)) return format;
  }
  throw ParameterError("--format",
                       "--format: '" + name + "' is not one of auto, folder, tum, euroc, kitti");
}

const char* InputFormatName(InputFormat format) {
  switch (format) {
    case InputFormat::kAuto:
      return "auto";
    case InputFormat::kFolder:
      return "folder";
    case InputFormat::kTum:
      return "tum";
    case InputFormat::kEuroc:
      return "euroc";
    case InputFormat::kKitti:
      return "kitti";
  }
  return "?";
}

InputFormat DetectDatasetFormat(const std::string& folder) {
  const fs::path root(folder);
  if (IsFile(root / "rgb.txt")) return InputFormat::kTum;
  if (!EurocCameraFolder(root).empty()) return InputFormat::kEuroc;
  if (!FindKitti(root).images.empty()) return InputFormat::kKitti;
  return InputFormat::kFolder;
}

DatasetListing ListDataset(const std::string& folder, InputFormat format) {
  if (format == InputFormat::kAuto) format = DetectDatasetFormat(folder);
  switch (format) {
    case InputFormat::kTum:
      return ListTum(folder);
    case InputFormat::kEuroc:
      return ListEuroc(folder);
    case InputFormat::kKitti:
      return ListKitti(folder);
    default:
      return ListPlainFolder(folder);
  }
}

std::vector<ListedImage> SampleAtRate(const std::vector<ListedImage>& images, double rate_hz) {
  if (rate_hz <= 0 || images.empty()) return images;
  const double period = 1.0 / rate_hz;
  std::vector<ListedImage> taken;
  const double start = images.front().timestamp;
  long long next = 0;  // the multiple of the period due next
  for (const ListedImage& image : images) {
    // 1e-6 s of slack: "1305031102.175304" read back is not exactly 1305031102.175304.
    const double elapsed = image.timestamp - start + 1e-6;
    if (elapsed < next * period) continue;
    taken.push_back(image);
    next = static_cast<long long>(std::floor(elapsed / period)) + 1;
  }
  return taken;
}

int NearestTime(const std::vector<double>& times, double time, double max_difference) {
  const auto after = std::lower_bound(times.begin(), times.end(), time);
  int nearest = -1;
  double best = max_difference;
  for (auto it = after == times.begin() ? after : after - 1; it != times.end() && it <= after;
       ++it) {
    if (std::abs(*it - time) <= best) {
      best = std::abs(*it - time);
      nearest = static_cast<int>(it - times.begin());
    }
  }
  return nearest;
}

void AddDepthFolder(const std::string& depth_folder, std::vector<ListedImage>& images) {
  if (!IsFolder(depth_folder)) throw InputError(depth_folder, "--depth: not a folder");
  int found = 0;
  for (ListedImage& image : images) {
    const std::string stem = fs::path(image.path).stem().string();
    image.depth_path.clear();
    for (const char* extension : {".png", ".tif", ".tiff", ".exr", ".pfm"}) {
      const fs::path candidate = fs::path(depth_folder) / (stem + extension);
      if (!IsFile(candidate)) continue;
      image.depth_path = candidate.string();
      ++found;
      break;
    }
  }
  if (found == 0 && !images.empty()) {
    throw InputError(depth_folder, "--depth: holds no depth map named as the images are (e.g. " +
                                       fs::path(images.front().path).stem().string() + ".png)");
  }
}

}  // namespace memloop
