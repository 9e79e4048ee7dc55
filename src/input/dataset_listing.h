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
};

struct DatasetListing {
  InputFormat format = InputFormat::kFolder;
  std::vector<ListedImage> images;
  std::string listing;  // the file that lists the images ("" for a plain folder)
};

// The layout `folder` is in: the first of TUM, EuRoC, KITTI whose listing file is there, else
// kFolder.
InputFormat DetectDatasetFormat(const std::string& folder);

// The images of `folder` read as `format` (kAuto: DetectDatasetFormat), in acquisition order.
// Throws InputError naming the listing file (and line) when it is missing, malformed, lists no
// image, has timestamps that go back in time, or (KITTI) has not one time per image.
DatasetListing ListDataset(const std::string& folder, InputFormat format);

// Of images in time order, those that first reach each multiple of 1 / rate_hz after the first.
std::vector<ListedImage> SampleAtRate(const std::vector<ListedImage>& images, double rate_hz);

}  // namespace memloop
