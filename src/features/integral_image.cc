#include "features/integral_image.h"

#include <opencv2/imgproc.hpp>

namespace memloop {

IntegralImage::IntegralImage(const cv::Mat& gray) : rows_(gray.rows), cols_(gray.cols) {
  cv::integral(gray, sum_, CV_32S);
}

float IntegralImage::HaarX(int row, int col, int size) const {
  const int half = size / 2;
  const int right = BoxSum(row - half, col, row + half - 1, col + half - 1);
  const int left = BoxSum(row - half, col - half, row + half - 1, col - 1);
  return static_cast<float>(right - left) / (half * size);
}

float IntegralImage::HaarY(int row, int col, int size) const {
  const int half = size / 2;
  const int bottom = BoxSum(row, col - half, row + half - 1, col + half - 1);
  const int top = BoxSum(row - half, col - half, row - 1, col + half - 1);
  return static_cast<float>(bottom - top) / (half * size);
}

}  // namespace memloop
