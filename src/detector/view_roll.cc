#include "detector/view_roll.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace memloop {
namespace {

constexpr double kMinSegmentPixels = 8;
constexpr double kMaxScaleChange = 3;
constexpr int kMinCorrespondences = 8;
constexpr int kMaxCorrespondences = 100;
constexpr int kHalfWindowDegrees = 7;  // with 1-degree bins: 15 degrees, +/- 7.5
constexpr double kMinAgreement = 0.25;

}  // namespace

ViewRoll EstimateViewRoll(const WordCorrespondences& matched) {
  ViewRoll roll;
  roll.correspondences = matched.size();
  if (roll.correspondences < kMinCorrespondences) return roll;
  std::array<double, 360> votes{};  // bin k: [k - 180, k - 179) degrees
  double total = 0;
  // At most kMaxCorrespondences, the first in word order (unrelated to where they are): 4,950
  // pairs, against 79,800 for 400 (3.7 ms, BM_ViewRoll).
  const int n = std::min(matched.size(), kMaxCorrespondences);
  constexpr double kMinSquared = kMinSegmentPixels * kMinSegmentPixels;
  constexpr double kMaxScaleSquared = kMaxScaleChange * kMaxScaleChange;
  for (int k = 0; k < n; ++k) {
    for (int l = k + 1; l < n; ++l) {
      const cv::Point2f a = matched.in_a[l] - matched.in_a[k];
      const cv::Point2f b = matched.in_b[l] - matched.in_b[k];
      const double squared_a = a.x * a.x + a.y * a.y, squared_b = b.x * b.x + b.y * b.y;
      if (squared_a < kMinSquared || squared_b < kMinSquared) continue;
      if (squared_b > kMaxScaleSquared * squared_a || squared_a > kMaxScaleSquared * squared_b) {
        continue;
      }
      // The angle from a's segment to b's (image axes).
      const double turn = std::atan2(a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y) * 180 / CV_PI;
      const int bin = std::min(359, static_cast<int>(std::floor(turn + 180)));
      votes[bin] += 1;
      total += 1;
    }
  }
  if (total == 0) return roll;
  // The densest window (circular), then the votes' mean angle inside it.
  double best = -1;
  int best_centre = 0;
  for (int centre = 0; centre < 360; ++centre) {
    double in_window = 0;
    for (int d = -kHalfWindowDegrees; d <= kHalfWindowDegrees; ++d) {
      in_window += votes[(centre + d + 360) % 360];
    }
    if (in_window > best) best = in_window, best_centre = centre;
  }
  double sum = 0;
  for (int d = -kHalfWindowDegrees; d <= kHalfWindowDegrees; ++d) {
    sum += votes[(best_centre + d + 360) % 360] * (best_centre + d + 0.5 - 180);
  }
  double degrees = sum / best;
  if (degrees > 180) degrees -= 360;
  if (degrees <= -180) degrees += 360;
  roll.degrees = degrees;
  roll.agreement = best / total;
  roll.known = roll.agreement >= kMinAgreement;
  return roll;
}

}  // namespace memloop
