// How unlikely an epipolar geometry is to be chance: the a-contrario number of false alarms
// (Moisan & Stival, "A probabilistic criterion to detect rigid point matches between two images
// and estimate the fundamental matrix", IJCV 2004). A fixed inlier count is not: at 3 pixels, a
// random point falls near an epipolar line 4x as often in a 240x192 image as in a 960x540 one,
// and 7 inliers are what any 7-point fit has.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace memloop {

// log10 of the number of false alarms of k of n correspondences lying within `pixels` of their
// epipolar lines, for a fundamental matrix fitted to 7 of them (up to 3 solutions) in images of
// `size`: log10(3 (n - 7) C(n, k) C(k, 7) alpha^(k - 7)), alpha = 2 pixels diagonal / area, the
// chance that a random point lies that near a line. Under 0: fewer than one such fit is
// expected among random correspondences.
double Log10FalseAlarms(int n, int k, double pixels, const cv::Size& size);

// Each correspondence's distance to its epipolar line, the larger of the two images'.
std::vector<double> EpipolarResiduals(const cv::Mat& fundamental,
                                      const std::vector<cv::Point2f>& in_a,
                                      const std::vector<cv::Point2f>& in_b);

// The lowest Log10FalseAlarms over k = 8..n, the k-th smallest residual as the distance (the
// geometry's own precision, not a fixed tolerance); +infinity under 8 residuals.
double LowestLog10FalseAlarms(std::vector<double> residuals, const cv::Size& size);

}  // namespace memloop
