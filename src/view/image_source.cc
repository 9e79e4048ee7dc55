#include "view/image_source.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "memloop/errors.h"

namespace memloop {

namespace {

namespace fs = std::filesystem;

// `image` no wider than `width`, as JPEG.
std::optional<std::vector<unsigned char>> Jpeg(const std::string& file, int width) {
  const cv::Mat image = cv::imread(file, cv::IMREAD_COLOR);
  if (image.empty()) return std::nullopt;
  cv::Mat scaled = image;
  if (image.cols > width) {
    cv::resize(image, scaled, cv::Size(width, std::max(1, image.rows * width / image.cols)), 0, 0,
               cv::INTER_AREA);
  }
  std::vector<unsigned char> bytes;
  cv::imencode(".jpg", scaled, bytes, {cv::IMWRITE_JPEG_QUALITY, 85});
  return bytes;
}

}  // namespace

ImageSource::ImageSource(const std::string& folder, size_t cached_thumbnails)
    : folder_(folder), capacity_(cached_thumbnails) {
  if (folder.empty()) return;
  std::error_code error;
  if (!fs::is_directory(folder, error)) {
    throw InputError(folder, std::string("not a folder of images (--images)") +
                                 (fs::exists(folder, error) ? "" : ": no such folder"));
  }
}

std::optional<std::string> ImageSource::File(const std::string& name) const {
  if (folder_.empty() || name.empty()) return std::nullopt;
  const fs::path relative(name);
  // The map's names are relative to the input it ran on: nothing outside the folder is served.
  if (relative.is_absolute()) return std::nullopt;
  for (const fs::path& part : relative) {
    if (part == "..") return std::nullopt;
  }
  std::error_code error;
  for (const fs::path& candidate :
       {fs::path(folder_) / relative, fs::path(folder_) / "images" / relative}) {
    if (fs::is_regular_file(candidate, error)) return candidate.string();
  }
  return std::nullopt;
}

std::optional<std::vector<unsigned char>> ImageSource::Thumbnail(const std::string& name) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto cached = cache_.find(name);
    if (cached != cache_.end()) {
      recent_.splice(recent_.begin(), recent_, cached->second.second);
      return cached->second.first;
    }
  }
  const std::optional<std::string> file = File(name);
  if (!file) return std::nullopt;
  std::optional<std::vector<unsigned char>> bytes = Jpeg(*file, kThumbnailWidth);
  if (!bytes) return std::nullopt;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (cache_.count(name) == 0) {
    recent_.push_front(name);
    cache_[name] = {*bytes, recent_.begin()};
    while (cache_.size() > capacity_) {
      cache_.erase(recent_.back());
      recent_.pop_back();
    }
  }
  return bytes;
}

std::optional<std::vector<unsigned char>> ImageSource::Full(const std::string& name) const {
  const std::optional<std::string> file = File(name);
  return file ? Jpeg(*file, kFullWidth) : std::nullopt;
}

}  // namespace memloop
