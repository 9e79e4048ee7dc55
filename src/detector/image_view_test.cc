#include "detector/image_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "memloop/errors.h"

namespace memloop {
namespace {

TEST(ImageViewTest, DepthMapsBecomeMetres) {
  cv::Mat millimetres(2, 3, CV_16UC1, cv::Scalar(0));
  millimetres.at<uint16_t>(0, 1) = 1500;
  millimetres.at<uint16_t>(1, 2) = 65535;
  const cv::Mat metres = DepthInMetres(millimetres, {3, 2});
  ASSERT_EQ(metres.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 1), 1.5f);
  EXPECT_FLOAT_EQ(metres.at<float>(1, 2), 65.535f);
  EXPECT_FLOAT_EQ(metres.at<float>(0, 0), 0);

  cv::Mat floats(2, 3, CV_32FC1, cv::Scalar(2.0f));
  floats.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  floats.at<float>(0, 1) = std::numeric_limits<float>::infinity();
  floats.at<float>(0, 2) = -1;
  const cv::Mat cleaned = DepthInMetres(floats, {3, 2});
  EXPECT_FLOAT_EQ(cleaned.at<float>(0, 0), 0);  // no reading, each of them
  EXPECT_FLOAT_EQ(cleaned.at<float>(0, 1), 0);
  EXPECT_FLOAT_EQ(cleaned.at<float>(0, 2), 0);
  EXPECT_FLOAT_EQ(cleaned.at<float>(1, 1), 2);
  EXPECT_FLOAT_EQ(floats.at<float>(1, 1), 2);  // the caller's map is not changed
  EXPECT_TRUE(std::isnan(floats.at<float>(0, 0)));

  EXPECT_TRUE(DepthInMetres(cv::Mat(), {3, 2}).empty());
}

TEST(ImageViewTest, DepthOfAnotherSizeOrTypeIsRefused) {
  try {
    DepthInMetres(cv::Mat(2, 3, CV_16UC1, cv::Scalar(0)), {6, 4});
    FAIL() << "a depth map of another size was taken";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("the depth map is 3x2, the image 6x4"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(DepthInMetres(cv::Mat(2, 3, CV_8UC1, cv::Scalar(0)), {3, 2}), InputError);
  EXPECT_THROW(DepthInMetres(cv::Mat(2, 3, CV_32FC3, cv::Scalar(0)), {3, 2}), InputError);
}

TEST(ImageViewTest, KeypointsAreBackProjectedThroughTheirDepth) {
  const CameraIntrinsics k{500, 400, 10, 5};
  cv::Mat depth(10, 20, CV_32FC1, cv::Scalar(0));
  depth.at<float>(7, 15) = 2;  // under the first keypoint
  depth.at<float>(2, 4) = 4;   // beside the second, at (3, 2) rounded
  depth.at<float>(2, 2) = 5;   // beside it too, farther from the camera
  Features features;
  features.keypoints = {cv::KeyPoint(15, 7, 3), cv::KeyPoint(3.2f, 2.4f, 3),
                        cv::KeyPoint(18, 0, 3)};
  features.descriptors = cv::Mat::eye(3, 4, CV_32F);
  const DescribedView view = ImageView(features, depth, k);
  ASSERT_EQ(view.points.size(), 3u);
  ASSERT_EQ(view.descriptors.rows, 3);
  // (15, 7) at 2 m: x = 2 (15 - 10) / 500 = 0.02, y = 2 (7 - 5) / 400 = 0.01.
  EXPECT_FLOAT_EQ(view.points[0].x, 0.02f);
  EXPECT_FLOAT_EQ(view.points[0].y, 0.01f);
  EXPECT_FLOAT_EQ(view.points[0].z, 2);
  // No reading under it: its neighbours' nearest the camera (an edge's foreground).
  EXPECT_FLOAT_EQ(view.points[1].z, 4);
  EXPECT_FLOAT_EQ(view.points[1].x, 4 * (3.2f - 10) / 500);
  EXPECT_FLOAT_EQ(view.points[2].z, 0);  // no reading within a pixel: no point

  EXPECT_TRUE(ImageView(features, cv::Mat(), k).points.empty());               // no depth map
  EXPECT_TRUE(ImageView(features, depth, CameraIntrinsics{}).points.empty());  // no camera
}

}  // namespace
}  // namespace memloop
