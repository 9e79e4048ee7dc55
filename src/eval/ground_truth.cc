#include "memloop/ground_truth.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "eval/ground_truth_mat.h"
#include "memloop/errors.h"

namespace memloop {
namespace {

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string Extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return Lowercase(path.substr(dot + 1));
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\"");
  const auto last = text.find_last_not_of(" \t\r\"");
  return first == std::string::npos ? "" : text.substr(first, last - first + 1);
}

void CheckSquare(const std::string& path, int rows, int cols) {
  if (rows == 0) throw InputError(path, "the ground truth is empty");
  if (rows != cols) {
    throw InputError(path, "the ground truth is " + std::to_string(rows) + "x" +
                               std::to_string(cols) + ", not square");
  }
}

cv::Mat LoadImage(const std::string& path) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(path, "cannot be read as an image");
  if (image.channels() != 1 || image.depth() != CV_8U) {
    throw InputError(path, "the ground truth image must be 8-bit grayscale");
  }
  CheckSquare(path, image.rows, image.cols);
  cv::Mat labels(image.size(), CV_8U, cv::Scalar(GroundTruth::kIgnored));
  labels.setTo(GroundTruth::kLoop, image == 255);
  labels.setTo(GroundTruth::kNone, image == 0);
  return labels;
}

cv::Mat LoadTextMatrix(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  std::vector<std::vector<unsigned char>> rows;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::vector<unsigned char> row;
    for (std::string field; fields >> field;) {
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (end != field.c_str() + field.size()) {
        throw InputError(path,
                         "line " + std::to_string(number) + ": '" + field + "' is not a number");
      }
      row.push_back(value == 1   ? GroundTruth::kLoop
                    : value == 0 ? GroundTruth::kNone
                                 : GroundTruth::kIgnored);
    }
    if (row.empty()) continue;
    if (!rows.empty() && row.size() != rows.front().size()) {
      throw InputError(path, "line " + std::to_string(number) + " has " +
                                 std::to_string(row.size()) + " values, line 1 has " +
                                 std::to_string(rows.front().size()));
    }
    rows.push_back(std::move(row));
  }
  CheckSquare(path, static_cast<int>(rows.size()),
              rows.empty() ? 0 : static_cast<int>(rows[0].size()));
  cv::Mat labels(static_cast<int>(rows.size()), static_cast<int>(rows.size()), CV_8U);
  for (int r = 0; r < labels.rows; ++r) std::copy(rows[r].begin(), rows[r].end(), labels.ptr(r));
  return labels;
}

cv::Mat LoadPairs(const std::string& path, const std::vector<std::string>& image_names,
                  int image_count) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  std::map<std::string, int> index_of_name;
  for (size_t i = 0; i < image_names.size(); ++i) {
    if (!image_names[i].empty()) index_of_name[image_names[i]] = static_cast<int>(i);
  }
  const auto resolve = [&](const std::string& field, int line) {
    const auto named = index_of_name.find(field);
    if (named != index_of_name.end()) return named->second;
    char* end = nullptr;
    const long index = std::strtol(field.c_str(), &end, 10);
    if (field.empty() || end != field.c_str() + field.size()) {
      throw InputError(path, "line " + std::to_string(line) + ": '" + field +
                                 "' is neither an image of the run nor an index");
    }
    if (index < 0 || index >= image_count) {
      throw InputError(path, "line " + std::to_string(line) + ": image index " + field +
                                 " is outside the run's " + std::to_string(image_count) +
                                 " images");
    }
    return static_cast<int>(index);
  };
  cv::Mat labels(image_count, image_count, CV_8U, cv::Scalar(GroundTruth::kNone));
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (Trim(line).empty()) continue;
    const auto comma = line.find(',');
    if (comma == std::string::npos || line.find(',', comma + 1) != std::string::npos) {
      throw InputError(path, "line " + std::to_string(number) + ": expected query,match");
    }
    const std::string first = Trim(line.substr(0, comma));
    const std::string second = Trim(line.substr(comma + 1));
    if (number == 1 && Lowercase(first) == "query") continue;  // header
    labels.at<unsigned char>(resolve(first, number), resolve(second, number)) = GroundTruth::kLoop;
  }
  return labels;
}

}  // namespace

std::vector<std::string> GroundTruth::DatasetFiles(const std::string& folder) {
  namespace fs = std::filesystem;
  const auto file = [&](const char* name) { return (fs::path(folder) / name).string(); };
  const auto exists = [](const std::string& path) {
    std::error_code error;
    return fs::is_regular_file(path, error);
  };
  for (const char* image : {"ground_truth.bmp", "ground_truth.png"}) {
    if (exists(file(image))) return {file(image)};
  }
  if (exists(file("ground_truth_pairs.csv"))) {
    std::vector<std::string> files = {file("ground_truth_pairs.csv")};
    if (exists(file("ground_truth_ignore.csv"))) files.push_back(file("ground_truth_ignore.csv"));
    return files;
  }
  if (exists(file("ground_truth.mat"))) return {file("ground_truth.mat")};
  throw InputError(folder,
                   "no ground truth in this folder: expected ground_truth.bmp, "
                   "ground_truth_pairs.csv (with ground_truth_ignore.csv) or ground_truth.mat");
}

GroundTruthFormat GroundTruth::ParseFormat(const std::string& name) {
  if (name == "auto") return GroundTruthFormat::kAuto;
  if (name == "mat") return GroundTruthFormat::kMat;
  if (name == "image") return GroundTruthFormat::kImage;
  if (name == "pairs") return GroundTruthFormat::kPairs;
  if (name == "matrix") return GroundTruthFormat::kMatrix;
  throw InputError(name, "unknown ground truth format (auto, mat, image, pairs, matrix)");
}

GroundTruth GroundTruth::Load(const std::string& path, GroundTruthFormat format,
                              const std::vector<std::string>& image_names, int image_count) {
  if (format == GroundTruthFormat::kAuto) {
    const std::string extension = Extension(path);
    format = extension == "mat"   ? GroundTruthFormat::kMat
             : extension == "csv" ? GroundTruthFormat::kPairs
             : (extension == "txt" || extension == "dat" || extension == "gt")
                 ? GroundTruthFormat::kMatrix
                 : GroundTruthFormat::kImage;
  }
  cv::Mat labels;
  switch (format) {
    case GroundTruthFormat::kMat:
      labels = LoadMatFile(path, image_count);
      break;
    case GroundTruthFormat::kImage:
      labels = LoadImage(path);
      break;
    case GroundTruthFormat::kPairs:
      labels = LoadPairs(path, image_names, image_count);
      break;
    default:
      labels = LoadTextMatrix(path);
      break;
  }
  if (labels.rows != image_count) {
    throw InputError(path, "the ground truth is " + std::to_string(labels.rows) + "x" +
                               std::to_string(labels.cols) + " but the run has " +
                               std::to_string(image_count) + " images");
  }
  return GroundTruth(labels);
}

GroundTruth::GroundTruth(const cv::Mat& labels) : labels_(labels.clone()) {
  // Symmetric: a loop either way is a loop; otherwise an ignored label wins over none.
  for (int a = 0; a < labels_.rows; ++a) {
    for (int b = 0; b < a; ++b) {
      unsigned char& ab = labels_.at<unsigned char>(a, b);
      unsigned char& ba = labels_.at<unsigned char>(b, a);
      const unsigned char merged =
          (ab == kLoop || ba == kLoop) ? static_cast<unsigned char>(kLoop) : std::max(ab, ba);
      ab = ba = merged;
    }
  }
}

GroundTruth::Label GroundTruth::At(ImageIndex a, ImageIndex b) const {
  if (a < 0 || b < 0 || a >= size() || b >= size() || a == b) return kNone;
  return static_cast<Label>(labels_.at<unsigned char>(a, b));
}

bool GroundTruth::HasEarlierMatch(ImageIndex query) const {
  for (ImageIndex match = 0; match < query && match < size(); ++match) {
    if (IsLoop(query, match)) return true;
  }
  return false;
}

GroundTruth GroundTruth::IgnoredAsLoops() const {
  cv::Mat labels = labels_.clone();
  for (ImageIndex query = 0; query < size(); ++query) {
    if (!HasEarlierMatch(query)) continue;
    for (ImageIndex match = 0; match < query; ++match) {
      if (At(query, match) != kIgnored) continue;
      labels.at<unsigned char>(query, match) = labels.at<unsigned char>(match, query) = kLoop;
    }
  }
  return GroundTruth(labels);
}

GroundTruth GroundTruth::WithIgnoredPairs(const std::string& path,
                                          const std::vector<std::string>& image_names) const {
  const cv::Mat listed = LoadPairs(path, image_names, size());
  cv::Mat labels = labels_.clone();
  labels.setTo(kIgnored, (listed == kLoop) & (labels_ == kNone));
  return GroundTruth(labels);
}

int GroundTruth::PairCount() const {
  int pairs = 0;
  for (int a = 0; a < size(); ++a) {
    for (int b = 0; b < a; ++b) pairs += IsLoop(a, b);
  }
  return pairs;
}

}  // namespace memloop
