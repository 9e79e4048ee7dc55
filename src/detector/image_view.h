// The image being processed as a loop closure's query view: its own keypoints and descriptors
// (not the words they became, nor an older image Rehearsal merged it with) and, given a depth
// map, each keypoint's 3-D point, from which a loop closure's transform is metric.
#pragma once

#include <opencv2/core.hpp>

#include "detector/descriptor_correspondences.h"
#include "memloop/feature_extractor.h"
#include "memloop/loop_geometry.h"

namespace memloop {

// A depth map given with an image, in metres (CV_32F, 0 where there is no reading): 16-bit
// unsigned in millimetres (ROS's 16UC1) or 32-bit float in metres (32FC1; NaN and infinities
// become 0). Empty when `depth` is. Throws InputError naming "depth" for another type or a size
// that is not the image's.
cv::Mat DepthInMetres(const cv::Mat& depth, const cv::Size& image_size);

// `depth_metres` (DepthInMetres) may be empty: then the view has no points. A keypoint's depth is
// its pixel's reading, or, when it has none, the reading of its 8 neighbours nearest the camera
// (keypoints sit on edges, where depth sensors leave holes, and belong to the foreground); none
// further away.
DescribedView ImageView(Features features, const cv::Mat& depth_metres,
                        const CameraIntrinsics& intrinsics);

}  // namespace memloop
