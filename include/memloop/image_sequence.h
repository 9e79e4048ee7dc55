// Images in acquisition order from a folder (natural numeric order: 2.jpg before 10.jpg), a
// video file or a live camera.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "memloop/types.h"

namespace memloop {

struct Frame {
  ImageIndex index = kNoImage;  // position in the sequence, counting unreadable files too
  std::string name;             // file name, or "frame N" of a video
  cv::Mat image;                // empty when unreadable
  std::string error;            // why it is unreadable ("" when readable)
  int dropped = 0;  // camera frames lost since the previous frame (the caller was too slow)
};

struct SequenceOptions {
  // Frames per second to take (the paper processes 1 Hz): a video is sampled by its timestamps, a
  // camera read at that pace. 0 = every frame (a camera: as fast as the caller takes them).
  double rate_hz = 0;
};

class ImageSequence {
 public:
  virtual ~ImageSequence() = default;
  // Throws InputError naming `path`: missing, an empty folder, a file that is not a video.
  static std::unique_ptr<ImageSequence> Open(const std::string& path,
                                             const SequenceOptions& options = {});
  // Camera `device` (0 = the first) through OpenCV; runs until the caller stops. Throws
  // InputError naming "camera N" when it cannot be opened.
  static std::unique_ptr<ImageSequence> OpenCamera(int device, const SequenceOptions& options = {});

  // The next frame; false at the end. An unreadable image gives a frame with `error` set, so the
  // caller can warn, skip and count it.
  virtual bool Next(Frame* frame) = 0;
  // Skips the frames before index `first` (a resumed run starts after the map's last image).
  // Folders skip without reading; videos decode and drop.
  virtual void SkipTo(ImageIndex first) {
    Frame frame;
    for (ImageIndex index = 0; index < first && Next(&frame); ++index) {
    }
  }
  // Number of frames, or -1 when unknown.
  virtual int size() const = 0;
};

// "a2.jpg" < "a10.jpg": digit runs compare as numbers.
bool NaturalLess(const std::string& a, const std::string& b);
// The regular, non-hidden files of `folder`, in natural order (names only).
std::vector<std::string> ListFolder(const std::string& folder);

}  // namespace memloop
