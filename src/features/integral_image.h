// An integral image with O(1) box sums, clamped to the image (Viola & Jones; SURF Sec. 3.1).
#pragma once

#include <algorithm>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace memloop {

class IntegralImage {
 public:
  // `gray`: 8-bit, one channel, of any size. The running sums are kept modulo 2^32 (unsigned
  // arithmetic, which wraps by definition), so a box sum is exact whenever the box itself sums
  // below 2^31, i.e. for any box of up to 2^31 / 255 pixels (8.4 Mpx), however large the image:
  // a bright 12 Mpx photo wraps the running sums, never a box. (A signed 32-bit table overflowed
  // there: undefined behaviour.)
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
    return BoxSumInside(row0, col0, row1, col1);
  }

  // Unclamped, for boxes known to lie inside the image (the detector's hot loop).
  int BoxSumInside(int row0, int col0, int row1, int col1) const {
    const uint32_t* top = Row(row0);
    const uint32_t* bottom = Row(row1 + 1);
    return static_cast<int>(bottom[col1 + 1] - top[col1 + 1] - bottom[col0] + top[col0]);
  }

  // Haar wavelet responses of side `size` (even) centred at (row, col): right minus left half,
  // and bottom minus top half, in intensity units per pixel.
  float HaarX(int row, int col, int size) const;
  float HaarY(int row, int col, int size) const;

 private:
  const uint32_t* Row(int row) const { return sums_.data() + static_cast<size_t>(row) * stride_; }

  std::vector<uint32_t> sums_;  // (rows + 1) x (cols + 1), row-major, modulo 2^32
  size_t stride_;
  int rows_;
  int cols_;
};

}  // namespace memloop
