// Depth maps registered to the images (RGB-D): read from files for a folder's images, checked
// against their image whatever their source.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "memloop/image_sequence.h"

namespace memloop {

// The depth map at `path` in metres, CV_32F (16-bit: `units_per_metre`; 32-bit float: metres),
// or empty with `error` saying why there is none.
cv::Mat ReadDepth(const std::string& path, double units_per_metre, std::string* error);

// A frame's depth map must be its image's size (registered to it); else the frame gets an error
// naming `source` (the depth map's file or topic) and neither is processed.
void CheckDepthMatchesImage(const std::string& source, Frame* frame);

}  // namespace memloop
