// An integral image with O(1) box sums, clamped to the image (Viola & Jones; SURF Sec. 3.1).
#pragma once

#include <algorithm>
#include <opencv2/core.hpp>

namespace memloop {

class IntegralImage {
 public:
  // `gray`: 8-bit, one channel. Sums fit in 32 bits up to 2^31 / 255 pixels (8 Mpx).
  explicit IntegralImage(const cv::Mat& gray);

  int rows() const { return rows_; }
  int cols() const { return cols_; }

  // Sum of the pixels in rows [row0, row1] and columns [col0, col1] (inclusive), with the box
  // clamped to the image; 0 when nothing is left.
  int BoxSum(int row0, int col0, int row1, int col1) const {
    row0 = std::max(row0, 0);
    col0 = std::max(col0, 0);
    row1 = std::min(row1, rows_ - 1);
    col1 = std::min(col1, cols_ - 1);
    if (row1 < row0 || col1 < col0) return 0;
    const int* top = sum_.ptr<int>(row0);
    const int* bottom = sum_.ptr<int>(row1 + 1);
    return bottom[col1 + 1] - top[col1 + 1] - bottom[col0] + top[col0];
  }

  // Unclamped, for boxes known to lie inside the image (the detector's hot loop).
  int BoxSumInside(int row0, int col0, int row1, int col1) const {
    const int* top = sum_.ptr<int>(row0);
    const int* bottom = sum_.ptr<int>(row1 + 1);
    return bottom[col1 + 1] - top[col1 + 1] - bottom[col0] + top[col0];
  }

  // Haar wavelet responses of side `size` (even) centred at (row, col): right minus left half,
  // and bottom minus top half, in intensity units per pixel.
  float HaarX(int row, int col, int size) const;
  float HaarY(int row, int col, int size) const;

 private:
  cv::Mat sum_;  // (rows + 1) x (cols + 1), CV_32S
  int rows_;
  int cols_;
};

}  // namespace memloop
