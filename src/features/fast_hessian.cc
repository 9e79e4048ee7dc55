#include "features/fast_hessian.h"

#include <cmath>

namespace memloop {
namespace {

// det(H) and the Laplacian's sign at every sample of one filter size. Sample (r, c) is pixel
// (r * step, c * step); samples where the filter does not fit in the image stay 0.
struct ResponseLayer {
  int filter_size = 0;
  int step = 1;
  cv::Mat det;        // CV_32F, rows / step x cols / step
  cv::Mat laplacian;  // CV_8S, +1 or -1
};

ResponseLayer ComputeLayer(const IntegralImage& image, int filter_size, int step) {
  ResponseLayer layer;
  layer.filter_size = filter_size;
  layer.step = step;
  const int rows = image.rows() / step;
  const int cols = image.cols() / step;
  layer.det = cv::Mat::zeros(rows, cols, CV_32F);
  layer.laplacian = cv::Mat::zeros(rows, cols, CV_8S);
  const int lobe = filter_size / 3;
  const int border = filter_size / 2;
  // Each lobe's sum is divided by its own area (as OpenCV's SURF, so that the Hessian threshold
  // is in intensity units): the three lobes of Dxx and Dyy share one area, Dxy's four too.
  const float inverse_lobe_area = 1.0f / ((2 * lobe - 1) * lobe);
  const float inverse_square_area = 1.0f / (lobe * lobe);
  for (int r = 0; r < rows; ++r) {
    const int y = r * step;
    if (y - border < 0 || y + border >= image.rows()) continue;
    float* det = layer.det.ptr<float>(r);
    signed char* laplacian = layer.laplacian.ptr<signed char>(r);
    for (int c = 0; c < cols; ++c) {
      const int x = c * step;
      if (x - border < 0 || x + border >= image.cols()) continue;
      // Dxx: lobes +1, -2, +1 side by side, each (2l-1) tall and l wide: whole - 3 * middle.
      const int dxx_whole = image.BoxSumInside(y - lobe + 1, x - border, y + lobe - 1, x + border);
      const int dxx_middle =
          image.BoxSumInside(y - lobe + 1, x - lobe / 2, y + lobe - 1, x + lobe / 2);
      // Dyy: the same, transposed.
      const int dyy_whole = image.BoxSumInside(y - border, x - lobe + 1, y + border, x + lobe - 1);
      const int dyy_middle =
          image.BoxSumInside(y - lobe / 2, x - lobe + 1, y + lobe / 2, x + lobe - 1);
      // Dxy: four l x l squares around the centre, + on the diagonal, - off it.
      const int dxy = image.BoxSumInside(y - lobe, x - lobe, y - 1, x - 1) +
                      image.BoxSumInside(y + 1, x + 1, y + lobe, x + lobe) -
                      image.BoxSumInside(y - lobe, x + 1, y - 1, x + lobe) -
                      image.BoxSumInside(y + 1, x - lobe, y + lobe, x - 1);
      const float dxx = (dxx_whole - 3 * dxx_middle) * inverse_lobe_area;
      const float dyy = (dyy_whole - 3 * dyy_middle) * inverse_lobe_area;
      const float dxy_normalized = dxy * inverse_square_area;
      // SURF eq. 3: det(H_approx) = Dxx Dyy - (0.9 Dxy)^2.
      det[c] = dxx * dyy - 0.81f * dxy_normalized * dxy_normalized;
      laplacian[c] = dxx + dyy >= 0 ? 1 : -1;
    }
  }
  return layer;
}

bool IsStrictMaximum(const ResponseLayer& below, const ResponseLayer& middle,
                     const ResponseLayer& above, int r, int c) {
  const float value = middle.det.at<float>(r, c);
  for (const ResponseLayer* layer : {&below, &middle, &above}) {
    for (int dr = -1; dr <= 1; ++dr) {
      const float* row = layer->det.ptr<float>(r + dr);
      for (int dc = -1; dc <= 1; ++dc) {
        if (layer == &middle && dr == 0 && dc == 0) continue;
        if (row[c + dc] >= value) return false;
      }
    }
  }
  return true;
}

// Fits a 3-D quadratic to the 3x3x3 neighbourhood (Brown & Lowe 2002) and returns the offset of
// its maximum in samples and layers; false when the fit fails or the maximum lies closer to
// another sample (an offset above 0.5).
bool InterpolateMaximum(const ResponseLayer& below, const ResponseLayer& middle,
                        const ResponseLayer& above, int r, int c, cv::Vec3d* offset) {
  const auto at = [&](const ResponseLayer& layer, int dr, int dc) {
    return static_cast<double>(layer.det.at<float>(r + dr, c + dc));
  };
  const double v = at(middle, 0, 0);
  const cv::Vec3d gradient((at(middle, 0, 1) - at(middle, 0, -1)) / 2,
                           (at(middle, 1, 0) - at(middle, -1, 0)) / 2,
                           (at(above, 0, 0) - at(below, 0, 0)) / 2);
  const double dxx = at(middle, 0, 1) + at(middle, 0, -1) - 2 * v;
  const double dyy = at(middle, 1, 0) + at(middle, -1, 0) - 2 * v;
  const double dss = at(above, 0, 0) + at(below, 0, 0) - 2 * v;
  const double dxy =
      (at(middle, 1, 1) - at(middle, 1, -1) - at(middle, -1, 1) + at(middle, -1, -1)) / 4;
  const double dxs = (at(above, 0, 1) - at(above, 0, -1) - at(below, 0, 1) + at(below, 0, -1)) / 4;
  const double dys = (at(above, 1, 0) - at(above, -1, 0) - at(below, 1, 0) + at(below, -1, 0)) / 4;
  const cv::Matx33d hessian(dxx, dxy, dxs, dxy, dyy, dys, dxs, dys, dss);
  cv::Vec3d solution;
  if (!cv::solve(hessian, -gradient, solution, cv::DECOMP_LU)) return false;
  for (int k = 0; k < 3; ++k) {
    if (!(std::fabs(solution[k]) <= 1.0)) return false;  // also rejects NaN
  }
  *offset = solution;
  return true;
}

}  // namespace

int FilterSize(int octave, int interval) { return 3 * ((2 << octave) * (interval + 1) + 1); }

std::vector<cv::KeyPoint> DetectFastHessian(const IntegralImage& image,
                                            const FastHessianOptions& options) {
  std::vector<cv::KeyPoint> keypoints;
  for (int octave = 0; octave < options.octaves; ++octave) {
    const int step = options.sample_step << octave;
    if (FilterSize(octave, 0) >= std::min(image.rows(), image.cols())) break;
    std::vector<ResponseLayer> layers;
    for (int interval = 0; interval < options.intervals; ++interval) {
      layers.push_back(ComputeLayer(image, FilterSize(octave, interval), step));
    }
    for (int interval = 1; interval + 1 < options.intervals; ++interval) {
      const ResponseLayer& below = layers[interval - 1];
      const ResponseLayer& middle = layers[interval];
      const ResponseLayer& above = layers[interval + 1];
      // Only where the largest filter of the three fits, one sample inside.
      const int margin = (above.filter_size / 2 + step - 1) / step + 1;
      for (int r = margin; r < middle.det.rows - margin; ++r) {
        const float* det = middle.det.ptr<float>(r);
        for (int c = margin; c < middle.det.cols - margin; ++c) {
          if (det[c] <= options.hessian_threshold) continue;
          if (!IsStrictMaximum(below, middle, above, r, c)) continue;
          cv::Vec3d offset;
          if (!InterpolateMaximum(below, middle, above, r, c, &offset)) continue;
          const float filter_step = static_cast<float>(above.filter_size - middle.filter_size);
          cv::KeyPoint keypoint;
          keypoint.pt = cv::Point2f(static_cast<float>((c + offset[0]) * step),
                                    static_cast<float>((r + offset[1]) * step));
          keypoint.size = middle.filter_size + static_cast<float>(offset[2]) * filter_step;
          keypoint.response = det[c];
          keypoint.octave = octave;
          keypoint.class_id = middle.laplacian.at<signed char>(r, c);
          keypoint.angle = -1;
          keypoints.push_back(keypoint);
        }
      }
    }
  }
  return keypoints;
}

}  // namespace memloop
