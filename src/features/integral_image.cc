#include "features/integral_image.h"

namespace memloop {

IntegralImage::IntegralImage(const cv::Mat& gray)
    : sums_((static_cast<size_t>(gray.rows) + 1) * (gray.cols + 1), 0),
      stride_(gray.cols + 1),
      rows_(gray.rows),
      cols_(gray.cols) {
  CV_Assert(gray.type() == CV_8UC1);
  for (int row = 0; row < rows_; ++row) {
    const uint8_t* pixels = gray.ptr<uint8_t>(row);
    const uint32_t* above = Row(row);
    uint32_t* sums = sums_.data() + (static_cast<size_t>(row) + 1) * stride_;
    uint32_t row_sum = 0;
    for (int col = 0; col < cols_; ++col) {
      row_sum += pixels[col];
      sums[col + 1] = above[col + 1] + row_sum;
    }
  }
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
