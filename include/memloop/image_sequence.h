// Images in acquisition order from a folder (natural numeric order: 2.jpg before 10.jpg), a
// dataset folder with timestamps (TUM RGB-D, EuRoC MAV, KITTI), a ROS bag (ROS 1 .bag, ROS 2
// sqlite3 storage), a video file or a live camera.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "memloop/types.h"

namespace memloop {

struct Frame {
  ImageIndex index = kNoImage;  // position in the sequence, counting unreadable files too
  std::string name;  // file name (a dataset's: as its listing names it), or "frame N" of a video
  double timestamp = kNoTimestamp;  // seconds (types.h)
  cv::Mat image;                    // empty when unreadable
  // Its depth map, registered to it, in metres (CV_32F, 0 where there is no reading); empty when
  // the input has none for it (Detector::Process(image, depth)).
  cv::Mat depth;
  std::string error;  // why it is unreadable ("" when readable)
  int dropped = 0;    // camera frames lost since the previous frame (the caller was too slow)
};

// How a folder lists its images (`memloop run --format`).
enum class InputFormat {
  kAuto,    // a dataset layout below when one is recognised, else a plain folder
  kFolder,  // every file of the folder, in natural order, no timestamps
  kTum,     // TUM RGB-D: rgb.txt ("timestamp path" lines) beside rgb/
  kEuroc,   // EuRoC MAV: mav0/cam0/data.csv ("timestamp [ns],filename") and mav0/cam0/data/
  kKitti,   // KITTI odometry (times.txt beside image_0/ or image_2/) or raw (image_00/data/ and
            // image_00/timestamps.txt)
};
// "auto", "folder", "tum", "euroc", "kitti"; ParameterError naming `--format` otherwise.
InputFormat ParseInputFormat(const std::string& name);
const char* InputFormatName(InputFormat format);

struct SequenceOptions {
  // Frames per second to take (the paper processes 1 Hz): a video or a dataset with timestamps is
  // sampled by its timestamps (the first frame reaching each multiple of 1 / rate), a camera read
  // at that pace. 0 = every frame (a camera: as fast as the caller takes them).
  double rate_hz = 0;
  InputFormat format = InputFormat::kAuto;
  // A bag's topic of sensor_msgs Image or CompressedImage; "" = its only image topic.
  std::string topic;
  // Depth maps registered to the images. A TUM RGB-D folder's depth.txt is read without asking.
  std::string depth_folder;  // a folder of depth maps named by the images' file stems
  std::string depth_topic;   // a bag's depth image topic (16UC1 or 32FC1), nearest time stamp
  // A 16-bit depth map's units per metre: 0 = the input's own (TUM: 5000; otherwise 1000,
  // millimetres, as ROS's 16UC1). A 32-bit float map is in metres.
  double depth_units_per_metre = 0;
};

class ImageSequence {
 public:
  virtual ~ImageSequence() = default;
  // Throws InputError naming `path`: missing, an empty folder, a file that is not a video, a bag
  // without the topic (the message lists its image topics).
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
  // The name Next() gives the frame at `index` without reading it; "" when that cannot be known
  // (a video, a camera). A resumed run checks with it that its input continues the map.
  virtual std::string NameOf(ImageIndex index) const {
    (void)index;
    return "";
  }
  // The layout the images are read in (kFolder for a video or a camera).
  virtual InputFormat format() const { return InputFormat::kFolder; }
};

// "a2.jpg" < "a10.jpg": digit runs compare as numbers.
bool NaturalLess(const std::string& a, const std::string& b);
// The regular, non-hidden files of `folder`, in natural order (names only).
std::vector<std::string> ListFolder(const std::string& folder);

}  // namespace memloop
