#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace memloop {

// The first two-dimensional numeric variable of a MATLAB .mat file (v4, v5 or v7.3, through
// libmatio), as GroundTruth labels: 1 = loop, 0 = none, other values = ignored. Throws InputError
// naming the file when the matrix is not square, is not `image_count` x `image_count` (checked
// before its data is read), or is truncated (v5: checked against the file's size).
cv::Mat LoadMatFile(const std::string& path, int image_count);

}  // namespace memloop
