#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace memloop {

// The first two-dimensional numeric variable of a MATLAB .mat file (v4, v5 or v7.3, through
// libmatio), as GroundTruth labels: 1 = loop, 0 = none, other values = ignored. Throws InputError.
cv::Mat LoadMatFile(const std::string& path);

}  // namespace memloop
