// The images of a map for the viewer: each found by the name the map recorded, in the folder
// given to `memloop view --images` (or its images/ subfolder, a data set's layout), and sent as
// JPEG: thumbnails made on demand and kept (the most recent ones, up to a bound), full images
// scaled down to a screen's width.
#pragma once

#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace memloop {

class ImageSource {
 public:
  // Throws InputError naming `folder` when it is not a readable folder; "" serves no image.
  explicit ImageSource(const std::string& folder, size_t cached_thumbnails = 4000);

  bool enabled() const { return !folder_.empty(); }
  // The file of `name` (the map's record of an image), nullopt when absent.
  std::optional<std::string> File(const std::string& name) const;
  // JPEG bytes: nullopt when the image is absent or cannot be decoded.
  std::optional<std::vector<unsigned char>> Thumbnail(const std::string& name);
  std::optional<std::vector<unsigned char>> Full(const std::string& name) const;

  static constexpr int kThumbnailWidth = 160;
  static constexpr int kFullWidth = 1024;

 private:
  std::string folder_;
  size_t capacity_;
  std::mutex mutex_;
  std::list<std::string> recent_;  // most recent first
  std::map<std::string, std::pair<std::vector<unsigned char>, std::list<std::string>::iterator>>
      cache_;
};

}  // namespace memloop
