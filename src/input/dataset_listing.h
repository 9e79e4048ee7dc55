// The image listings of dataset folders with timestamps: TUM RGB-D (rgb.txt), EuRoC MAV
// (mav0/cam0/data.csv), KITTI odometry (times.txt) and raw (image_00/timestamps.txt).
#pragma once

#include <string>
#include <vector>

#include "memloop/image_sequence.h"

namespace memloop {

struct ListedImage {
  std::string name;  // as the listing names it (e.g. "rgb/1305031102.175304.png")
  std::string path;  // the file to read
  double timestamp = kNoTimestamp;
  std::string depth_path;  // its depth map ("" when none)
};

struct DatasetListing {
  InputFormat format = InputFormat::kFolder;
  std::vector<ListedImage> images;
  std::string listing;  // the file that lists the images ("" for a plain folder)
  // Units of a 16-bit depth map per metre, when the format says (TUM: 5000); 0 when it does not.
  double depth_units_per_metre = 0;
};

// `--depth DIR`: each image's depth map is DIR's file of the image's stem (.png, .tif, .tiff,
// .exr, .pfm). Throws InputError naming DIR when it is not a folder or holds none of them.
void AddDepthFolder(const std::string& depth_folder, std::vector<ListedImage>& images);

// The layout `folder` is in: the first of TUM, EuRoC, KITTI whose listing file is there, else
// kFolder.
InputFormat DetectDatasetFormat(const std::string& folder);

// The images of `folder` read as `format` (kAuto: DetectDatasetFormat), in acquisition order.
// Throws InputError naming the listing file (and line) when it is missing, malformed, lists no
// image, has timestamps that go back in time, or (KITTI) has not one time per image.
DatasetListing ListDataset(const std::string& folder, InputFormat format);

// The index of the time in `times` (increasing) nearest `time` within `max_difference` seconds;
// -1 when none is (how TUM's associate.py pairs depth with colour, and a bag's depth topic).
int NearestTime(const std::vector<double>& times, double time, double max_difference);

// Of images in time order, those that first reach each multiple of 1 / rate_hz after the first.
std::vector<ListedImage> SampleAtRate(const std::vector<ListedImage>& images, double rate_hz);

}  // namespace memloop
