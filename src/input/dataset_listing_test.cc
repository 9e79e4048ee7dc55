#include "input/dataset_listing.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "expect_input_error.h"
#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

void WriteImage(const fs::path& path) {
  fs::create_directories(path.parent_path());
  cv::imwrite(path.string(), cv::Mat(12, 16, CV_8UC3, cv::Scalar(40, 80, 120)));
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::vector<std::string> Names(const std::vector<ListedImage>& images) {
  std::vector<std::string> names;
  for (const ListedImage& image : images) names.push_back(image.name);
  return names;
}

using testing::ExpectInputError;

TEST(DatasetListingTest, TumListingWithCommentsInTimeOrder) {
  testing::TempDir dir;
  const fs::path root = dir.path();
  WriteText(root / "rgb.txt",
            "# color images\n# file: 'rgbd_dataset_freiburg1_rpy.bag'\n# timestamp filename\n"
            "1305031229.728891 rgb/1305031229.728891.png\r\n"
            "\n1305031229.760898 rgb/1305031229.760898.png\n");
  WriteImage(root / "rgb" / "1305031229.728891.png");
  WriteImage(root / "rgb" / "1305031229.760898.png");
  WriteImage(root / "depth" / "1305031229.7.png");  // not listed: not an image of the run
  EXPECT_EQ(DetectDatasetFormat(root.string()), InputFormat::kTum);
  const DatasetListing listing = ListDataset(root.string(), InputFormat::kAuto);
  EXPECT_EQ(listing.format, InputFormat::kTum);
  ASSERT_EQ(listing.images.size(), 2u);
  EXPECT_EQ(listing.images[0].name, "rgb/1305031229.728891.png");
  EXPECT_EQ(listing.images[0].path, (root / "rgb" / "1305031229.728891.png").string());
  EXPECT_DOUBLE_EQ(listing.images[1].timestamp, 1305031229.760898);

  auto sequence = ImageSequence::Open(root.string());
  EXPECT_EQ(sequence->format(), InputFormat::kTum);
  EXPECT_EQ(sequence->size(), 2);
  EXPECT_EQ(sequence->NameOf(1), "rgb/1305031229.760898.png");
  EXPECT_EQ(sequence->NameOf(2), "");
  Frame frame;
  ASSERT_TRUE(sequence->Next(&frame));
  EXPECT_TRUE(frame.error.empty()) << frame.error;
  EXPECT_EQ(frame.image.cols, 16);
  EXPECT_DOUBLE_EQ(frame.timestamp, 1305031229.728891);
}

TEST(DatasetListingTest, TumMalformedLinesAndTimeGoingBackAreRefusedByLine) {
  testing::TempDir dir;
  const std::string listing = dir.File("rgb.txt");
  const auto open = [&] { ListDataset(dir.path().string(), InputFormat::kTum); };
  WriteText(listing, "# x\n1.0 a.png\n2.0\n");
  ExpectInputError(open, listing, "line 3: expected 'timestamp filename'");
  WriteText(listing, "1.0 a.png\nnoon b.png\n");
  ExpectInputError(open, listing, "line 2: 'noon' is not a time stamp");
  WriteText(listing, "2.0 a.png\n1.0 b.png\n");
  ExpectInputError(open, listing, "line 2: time stamp before the previous line's");
  WriteText(listing, "# only comments\n");
  ExpectInputError(open, listing, "the listing holds no image");
  fs::remove(listing);  // named as EuRoC and KITTI folders are (before: "rgb.txt: cannot be read")
  ExpectInputError(open, dir.path().string(), "not a TUM folder (no rgb.txt)");
}

// A TUM RGB-D folder's depth.txt: each image takes the depth map nearest its time stamp within
// 20 ms (the benchmark's associate.py), 5000 units a metre.
TEST(DatasetListingTest, TumDepthListingGivesEachImageTheNearestDepthMap) {
  testing::TempDir dir;
  const fs::path root = dir.path();
  WriteText(root / "rgb.txt", "1.000 rgb/1.png\n1.033 rgb/2.png\n1.500 rgb/3.png\n");
  WriteText(root / "depth.txt",
            "# depth maps\n1.010 depth/a.png\n1.040 depth/b.png\n1.300 depth/c.png\n");
  const DatasetListing listing = ListDataset(root.string(), InputFormat::kAuto);
  ASSERT_EQ(listing.images.size(), 3u);
  EXPECT_EQ(listing.images[0].depth_path, (root / "depth" / "a.png").string());  // 10 ms
  EXPECT_EQ(listing.images[1].depth_path, (root / "depth" / "b.png").string());  // 7 ms, not 23
  EXPECT_EQ(listing.images[2].depth_path, "");  // 200 ms from the nearest: none
  EXPECT_DOUBLE_EQ(listing.depth_units_per_metre, 5000);

  WriteText(root / "depth.txt", "1.010 depth/a.png\n1.040\n");
  ExpectInputError([&] { ListDataset(root.string(), InputFormat::kAuto); },
                   (root / "depth.txt").string(), "line 2: expected 'timestamp filename'");
}

TEST(DatasetListingTest, NearestTimeWithinTheTolerance) {
  const std::vector<double> times = {1.0, 1.03, 1.5};
  EXPECT_EQ(NearestTime(times, 1.01, 0.02), 0);
  EXPECT_EQ(NearestTime(times, 1.02, 0.02), 1);  // 10 ms from 1.03, 20 from 1.0
  EXPECT_EQ(NearestTime(times, 0.99, 0.02), 0);  // before the first
  EXPECT_EQ(NearestTime(times, 1.3, 0.02), -1);  // 200 ms from either
  EXPECT_EQ(NearestTime(times, 1.51, 0.02), 2);  // after the last, within
  EXPECT_EQ(NearestTime(times, 2.0, 0.02), -1);
  EXPECT_EQ(NearestTime({}, 1.0, 0.02), -1);
}

// --depth DIR: each image's depth map is the file of its stem (PNG, TIFF, EXR or PFM there).
TEST(DatasetListingTest, DepthFolderGivesEachImageTheMapOfItsName) {
  testing::TempDir dir;
  std::vector<ListedImage> images(3);
  for (int i = 0; i < 3; ++i) images[i].path = dir.File("images/" + std::to_string(i + 1) + ".jpg");
  WriteText(dir.path() / "depth" / "1.png", "");
  WriteText(dir.path() / "depth" / "2.tiff", "");
  WriteText(dir.path() / "depth" / "2.jpg", "");  // not a depth map's format
  AddDepthFolder(dir.File("depth"), images);
  EXPECT_EQ(images[0].depth_path, dir.File("depth/1.png"));
  EXPECT_EQ(images[1].depth_path, dir.File("depth/2.tiff"));
  EXPECT_EQ(images[2].depth_path, "");  // that image goes without
  ExpectInputError([&] { AddDepthFolder(dir.File("images"), images); }, dir.File("images"),
                   "--depth: not a folder");
  fs::remove(dir.path() / "depth" / "1.png");
  fs::remove(dir.path() / "depth" / "2.tiff");
  ExpectInputError([&] { AddDepthFolder(dir.File("depth"), images); }, dir.File("depth"),
                   "--depth: holds no depth map named as the images are (e.g. 1.png)");
}

TEST(DatasetListingTest, ListedImageThatIsMissingIsAFrameWithAnError) {
  testing::TempDir dir;
  WriteText(dir.path() / "rgb.txt", "1.0 rgb/1.png\n1.5 rgb/gone.png\n");
  WriteImage(dir.path() / "rgb" / "1.png");
  auto sequence = ImageSequence::Open(dir.path().string());
  Frame frame;
  ASSERT_TRUE(sequence->Next(&frame));
  EXPECT_TRUE(frame.error.empty());
  ASSERT_TRUE(sequence->Next(&frame));
  EXPECT_EQ(frame.name, "rgb/gone.png");
  EXPECT_EQ(frame.index, 1);
  EXPECT_FALSE(frame.error.empty());
  EXPECT_FALSE(sequence->Next(&frame));
}

TEST(DatasetListingTest, EurocFromTheSequenceTheMavOrTheCameraFolder) {
  testing::TempDir dir;
  const fs::path camera = dir.path() / "mav0" / "cam0";
  WriteText(camera / "data.csv",
            "#timestamp [ns],filename\n1403636579763555584,1403636579763555584.png\n"
            "1403636579813555456,1403636579813555456.png\n");
  WriteImage(camera / "data" / "1403636579763555584.png");
  WriteImage(camera / "data" / "1403636579813555456.png");
  for (const fs::path& root : {dir.path(), dir.path() / "mav0", camera}) {
    EXPECT_EQ(DetectDatasetFormat(root.string()), InputFormat::kEuroc) << root;
    const DatasetListing listing = ListDataset(root.string(), InputFormat::kAuto);
    ASSERT_EQ(listing.images.size(), 2u);
    EXPECT_EQ(listing.images[1].name, "1403636579813555456.png");
    EXPECT_EQ(listing.images[1].path, (camera / "data" / "1403636579813555456.png").string());
    // 1403636579813555456 ns, to a double's precision
    EXPECT_NEAR(listing.images[1].timestamp, 1403636579.813555456, 1e-6);
  }
  WriteText(camera / "data.csv", "#timestamp [ns],filename\n14036365797635,\n");
  ExpectInputError([&] { ListDataset(camera.string(), InputFormat::kEuroc); },
                   (camera / "data.csv").string(), "line 2: expected 'timestamp in ns,filename'");
  ExpectInputError(
      [&] { ListDataset((dir.path() / "mav0" / "cam0" / "data").string(), InputFormat::kEuroc); },
      (camera / "data").string(), "not a EuRoC folder");
}

TEST(DatasetListingTest, KittiOdometryNeedsOneTimePerImage) {
  testing::TempDir dir;
  for (const char* name : {"000000.png", "000001.png", "000002.png"}) {
    WriteImage(dir.path() / "image_0" / name);
    WriteImage(dir.path() / "image_1" / name);  // the right camera: not read
  }
  WriteText(dir.path() / "times.txt", "0.000000e+00\n1.036224e-01\n2.072599e-01\n");
  EXPECT_EQ(DetectDatasetFormat(dir.path().string()), InputFormat::kKitti);
  const DatasetListing listing = ListDataset(dir.path().string(), InputFormat::kAuto);
  EXPECT_EQ(Names(listing.images),
            (std::vector<std::string>{"000000.png", "000001.png", "000002.png"}));
  EXPECT_DOUBLE_EQ(listing.images[2].timestamp, 0.2072599);
  EXPECT_EQ(listing.images[0].path, (dir.path() / "image_0" / "000000.png").string());

  WriteText(dir.path() / "times.txt", "0.0\n0.1\n");
  ExpectInputError([&] { ListDataset(dir.path().string(), InputFormat::kKitti); },
                   dir.File("times.txt"), "2 times for 3 images");
}

TEST(DatasetListingTest, KittiRawDatesAreSecondsSince1970) {
  testing::TempDir dir;
  WriteImage(dir.path() / "image_00" / "data" / "0000000000.png");
  WriteImage(dir.path() / "image_00" / "data" / "0000000001.png");
  WriteText(dir.path() / "image_00" / "timestamps.txt",
            "1970-01-01 00:00:01.500000000\n2011-09-26 13:02:25.964389445\n");
  const DatasetListing listing = ListDataset(dir.path().string(), InputFormat::kAuto);
  EXPECT_EQ(listing.format, InputFormat::kKitti);
  ASSERT_EQ(listing.images.size(), 2u);
  EXPECT_DOUBLE_EQ(listing.images[0].timestamp, 1.5);
  // 2011-09-26 00:00 UTC is day 15243 since 1970: 15243 * 86400 + 13 * 3600 + 2 * 60 + 25.96...
  EXPECT_NEAR(listing.images[1].timestamp, 1317042145.964389445, 1e-6);
  WriteText(dir.path() / "image_00" / "timestamps.txt", "1970-01-01 00:00:01.5\nyesterday\n");
  ExpectInputError([&] { ListDataset(dir.path().string(), InputFormat::kKitti); },
                   (dir.path() / "image_00" / "timestamps.txt").string(),
                   "line 2: 'yesterday' is not a time");
}

TEST(DatasetListingTest, RateTakesTheFirstImageReachingEachPeriod) {
  std::vector<ListedImage> images;
  for (double t : {10.0, 10.3, 10.6, 10.9, 11.2, 11.5, 13.1, 13.4}) images.push_back({"", "", t});
  std::vector<double> taken;
  for (const ListedImage& image : SampleAtRate(images, 1.0)) taken.push_back(image.timestamp);
  // Due at 10, 11, 12, 13 s: 11.2 is the first at or after 11; nothing reaches 12 before 13.1,
  // which stands for both 12 and 13.
  EXPECT_EQ(taken, (std::vector<double>{10.0, 11.2, 13.1}));
  EXPECT_EQ(SampleAtRate(images, 0).size(), images.size());
}

TEST(DatasetListingTest, RateOnATimestampedFolderAndRefusals) {
  testing::TempDir dir;
  std::string listing;
  for (int i = 0; i < 10; ++i) {
    const std::string name = "rgb/" + std::to_string(i) + ".png";
    WriteImage(dir.path() / name);
    listing += std::to_string(100 + 0.1 * i) + " " + name + "\n";
  }
  WriteText(dir.path() / "rgb.txt", listing);
  SequenceOptions options;
  options.rate_hz = 2;  // every 0.5 s of 0.1 s apart images: 0 and 5
  auto sequence = ImageSequence::Open(dir.path().string(), options);
  EXPECT_EQ(sequence->size(), 2);
  EXPECT_EQ(sequence->NameOf(1), "rgb/5.png");

  // --format folder reads every file of the folder, without timestamps: no rate.
  options.format = InputFormat::kFolder;
  ExpectInputError([&] { ImageSequence::Open(dir.path().string(), options); }, dir.path().string(),
                   "a rate needs timestamps");
  options.rate_hz = 0;
  EXPECT_EQ(ImageSequence::Open(dir.path().string(), options)->size(), 1);  // rgb.txt only
  options.format = InputFormat::kEuroc;
  ExpectInputError([&] { ImageSequence::Open(dir.path().string(), options); }, dir.path().string(),
                   "not a EuRoC folder");
  ExpectInputError([&] { ImageSequence::Open(dir.File("rgb.txt"), options); }, dir.File("rgb.txt"),
                   "--format euroc reads a folder");
  EXPECT_EQ(ParseInputFormat("kitti"), InputFormat::kKitti);
  EXPECT_THROW(ParseInputFormat("rosbag"), ParameterError);
}

}  // namespace
}  // namespace memloop
