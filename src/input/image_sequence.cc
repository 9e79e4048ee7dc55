#include "memloop/image_sequence.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "input/bag_sequence.h"
#include "input/capture_sequence.h"
#include "input/dataset_listing.h"
#include "input/depth_map.h"
#include "memloop/errors.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// libjpeg decodes a JPEG cut short without an error (the missing rows grey), and OpenCV's only
// word is a warning on stderr. A complete JPEG ends with its EOI marker (FF D9), which cannot
// occur inside the entropy-coded data; a few writers append bytes after it, so the last
// kilobyte is searched.
bool IsTruncatedJpeg(const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return false;  // not a JPEG
  const size_t from = bytes.size() > 1024 ? bytes.size() - 1024 : 2;
  for (size_t i = bytes.size() - 1; i > from; --i) {
    if (bytes[i - 1] == 0xFF && bytes[i] == 0xD9) return false;
  }
  return true;
}

// The image at `path` in colour, or `error` saying why there is none.
cv::Mat ReadImage(const std::string& path, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), {});
  if (!in.good() && !in.eof()) {
    *error = "cannot be read";
    return cv::Mat();
  }
  if (IsTruncatedJpeg(bytes)) {
    *error = "truncated JPEG (no end-of-image marker)";
    return cv::Mat();
  }
  cv::Mat image;
  try {
    if (!bytes.empty()) image = cv::imdecode(bytes, cv::IMREAD_COLOR);
  } catch (const cv::Exception& exception) {
    *error = exception.what();
  }
  if (image.empty() && error->empty()) {
    *error = "not a readable image (corrupt, truncated or not an image)";
  }
  return image;
}

// A plain folder or a dataset's listing: images known by name before any is read.
class ListedSequence : public ImageSequence {
 public:
  ListedSequence(InputFormat format, std::vector<ListedImage> images, double depth_units_per_metre)
      : format_(format),
        images_(std::move(images)),
        depth_units_per_metre_(depth_units_per_metre) {}

  void SkipTo(ImageIndex first) override {
    next_ = std::max(next_, std::min(images_.size(), static_cast<size_t>(std::max(first, 0))));
  }

  bool Next(Frame* frame) override {
    if (next_ >= images_.size()) return false;
    const ListedImage& image = images_[next_];
    frame->index = static_cast<ImageIndex>(next_++);
    frame->name = image.name;
    frame->timestamp = image.timestamp;
    frame->error.clear();
    frame->image = ReadImage(image.path, &frame->error);
    frame->depth.release();
    if (frame->error.empty() && !image.depth_path.empty()) {
      frame->depth = ReadDepth(image.depth_path, depth_units_per_metre_, &frame->error);
      if (!frame->error.empty()) frame->image.release();
      CheckDepthMatchesImage(image.depth_path, frame);
    }
    return true;
  }
  int size() const override { return static_cast<int>(images_.size()); }
  std::string NameOf(ImageIndex index) const override {
    return index >= 0 && static_cast<size_t>(index) < images_.size() ? images_[index].name : "";
  }
  InputFormat format() const override { return format_; }

 private:
  InputFormat format_;
  std::vector<ListedImage> images_;
  double depth_units_per_metre_;
  size_t next_ = 0;
};

}  // namespace

bool NaturalLess(const std::string& a, const std::string& b) {
  size_t i = 0;
  size_t j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t end_i = i;
      size_t end_j = j;
      while (end_i < a.size() && std::isdigit(static_cast<unsigned char>(a[end_i]))) ++end_i;
      while (end_j < b.size() && std::isdigit(static_cast<unsigned char>(b[end_j]))) ++end_j;
      std::string digits_a = a.substr(i, end_i - i);
      std::string digits_b = b.substr(j, end_j - j);
      digits_a.erase(0, std::min(digits_a.find_first_not_of('0'), digits_a.size() - 1));
      digits_b.erase(0, std::min(digits_b.find_first_not_of('0'), digits_b.size() - 1));
      if (digits_a.size() != digits_b.size()) return digits_a.size() < digits_b.size();
      if (digits_a != digits_b) return digits_a < digits_b;
      i = end_i;
      j = end_j;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  if (a.size() - i != b.size() - j) return a.size() - i < b.size() - j;
  return a < b;  // equal up to leading zeros: any fixed order
}

std::vector<std::string> ListFolder(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end;
       entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    // An entry whose type cannot be known (a looping symlink) is kept: reading it fails, and
    // the run skips and counts it like a corrupt image instead of stopping.
    std::error_code type_error;
    const bool regular = entry->is_regular_file(type_error);
    if (regular || type_error) names.push_back(name);
  }
  if (error) throw InputError(folder, "cannot list the folder (" + error.message() + ")");
  std::sort(names.begin(), names.end(), NaturalLess);
  return names;
}

namespace {

// NaN passes `rate_hz > 0` checks as false and `rate_hz <= 0` ones as false too: refused here.
void CheckRate(const SequenceOptions& options) {
  if (!std::isfinite(options.depth_units_per_metre) || options.depth_units_per_metre < 0) {
    throw ParameterError("--depth-scale",
                         "--depth-scale: must be a 16-bit depth map's units per metre, over 0 "
                         "(1000: millimetres), not " +
                             std::to_string(options.depth_units_per_metre));
  }
  if (!std::isfinite(options.rate_hz) || options.rate_hz < 0) {
    throw ParameterError("--rate",
                         "--rate: must be a finite number of frames per second (0: "
                         "every frame), not " +
                             std::to_string(options.rate_hz));
  }
}

}  // namespace

std::unique_ptr<ImageSequence> ImageSequence::Open(const std::string& path,
                                                   const SequenceOptions& options) {
  CheckRate(options);
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) throw InputError(path, "no such file or folder");
  if (IsBag(path)) {
    if (options.format != InputFormat::kAuto) {
      throw InputError(path, std::string("--format ") + InputFormatName(options.format) +
                                 " reads a folder of images, and this is a bag (--topic "
                                 "chooses its images)");
    }
    if (!options.depth_folder.empty()) {
      throw InputError(path,
                       "--depth reads a folder of depth maps; a bag's are a topic "
                       "(--depth-topic)");
    }
    return OpenBag(path, options);
  }
  if (!options.depth_topic.empty()) {
    throw InputError(path, "--depth-topic " + options.depth_topic +
                               " names a topic of a bag, and this is not one (--depth DIR gives a "
                               "folder's depth maps)");
  }
  if (!options.topic.empty()) {
    throw InputError(path, "--topic " + options.topic +
                               " names a topic of a bag, and this is not one (a .bag file, a "
                               ".db3 file or a ROS 2 bag folder with metadata.yaml)");
  }
  if (fs::is_directory(status)) {
    DatasetListing listing = ListDataset(path, options.format);
    if (options.rate_hz > 0 && listing.format == InputFormat::kFolder) {
      throw InputError(path,
                       "a rate needs timestamps: a dataset folder (TUM rgb.txt, EuRoC data.csv, "
                       "KITTI times.txt), a video or a camera, not a plain folder of images");
    }
    if (!options.depth_folder.empty()) {
      AddDepthFolder(options.depth_folder, listing.images);
      listing.depth_units_per_metre = 1000;  // millimetres, as ROS's 16UC1 (not TUM's)
    }
    const double units = options.depth_units_per_metre > 0   ? options.depth_units_per_metre
                         : listing.depth_units_per_metre > 0 ? listing.depth_units_per_metre
                                                             : 1000;
    return std::make_unique<ListedSequence>(listing.format,
                                            SampleAtRate(listing.images, options.rate_hz), units);
  }
  if (options.format != InputFormat::kAuto) {
    throw InputError(path, std::string("--format ") + InputFormatName(options.format) +
                               " reads a folder, and this is a file (a video needs no --format)");
  }
  if (!options.depth_folder.empty()) {
    throw InputError(path, "--depth gives depth maps to a folder's images, and this is a video");
  }
  return OpenVideo(path, options.rate_hz);
}

void CheckSequenceOptions(const SequenceOptions& options) { CheckRate(options); }

}  // namespace memloop
