#include "memloop/ground_truth.h"

#include <gtest/gtest.h>
#include <matio.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

class GroundTruthTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_.File(name)) << text;
    return dir_.File(name);
  }
  // Loading must fail naming the file and containing `reason`.
  void ExpectError(const std::string& path, const std::string& reason, int count = 4,
                   GroundTruthFormat format = GroundTruthFormat::kAuto) {
    try {
      GroundTruth::Load(path, format, names_, count);
      FAIL() << "accepted " << path;
    } catch (const InputError& error) {
      EXPECT_EQ(error.path(), path);
      EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
  }
  testing::TempDir dir_;
  std::vector<std::string> names_ = {"a.jpg", "b.jpg", "c.jpg", "d.jpg"};
};

// 4 images: 2 ~ 0 and 3 ~ 1 are loops; (3, 0) ignored in the image form.
void ExpectExample(const GroundTruth& truth, bool with_ignored) {
  EXPECT_EQ(truth.size(), 4);
  EXPECT_TRUE(truth.IsLoop(2, 0));
  EXPECT_TRUE(truth.IsLoop(0, 2));  // symmetric
  EXPECT_TRUE(truth.IsLoop(3, 1));
  EXPECT_FALSE(truth.IsLoop(1, 0));
  EXPECT_EQ(truth.At(3, 0), with_ignored ? GroundTruth::kIgnored : GroundTruth::kNone);
  EXPECT_EQ(truth.PairCount(), 2);
  EXPECT_FALSE(truth.HasEarlierMatch(1));
  EXPECT_TRUE(truth.HasEarlierMatch(2));
}

TEST_F(GroundTruthTest, Image255IsLoopOtherValuesIgnored) {
  cv::Mat image(4, 4, CV_8U, cv::Scalar(0));
  image.at<unsigned char>(2, 0) = 255;
  image.at<unsigned char>(3, 1) = 255;
  image.at<unsigned char>(3, 0) = 128;
  cv::imwrite(dir_.File("gt.png"), image);
  ExpectExample(GroundTruth::Load(dir_.File("gt.png"), GroundTruthFormat::kAuto, names_, 4), true);
}

TEST_F(GroundTruthTest, PairsByNameOrIndex) {
  ExpectExample(GroundTruth::Load(Write("names.csv", "query,match\nc.jpg,a.jpg\nd.jpg,b.jpg\n"),
                                  GroundTruthFormat::kAuto, names_, 4),
                false);
  ExpectExample(
      GroundTruth::Load(Write("indices.csv", "2,0\n3, 1\n"), GroundTruthFormat::kAuto, names_, 4),
      false);
}

// A CSV of loop pairs says nothing of the pairs to ignore; a second CSV does. A listed pair that
// is a loop stays one, either way round; a pair listed in neither stays none.
TEST_F(GroundTruthTest, IgnoredPairsFromASecondCsv) {
  const GroundTruth pairs =
      GroundTruth::Load(Write("pairs.csv", "query,match\nc.jpg,a.jpg\nd.jpg,b.jpg\n"),
                        GroundTruthFormat::kAuto, names_, 4);
  ExpectExample(pairs, false);
  const GroundTruth ignored = pairs.WithIgnoredPairs(
      Write("ignore.csv", "query,match\nd.jpg,a.jpg\nb.jpg,d.jpg\n"), names_);
  ExpectExample(ignored, true);
  EXPECT_EQ(ignored.At(0, 3), GroundTruth::kIgnored);
  EXPECT_TRUE(ignored.IsLoop(3, 1));  // listed too, still a loop
  EXPECT_EQ(ignored.At(2, 1), GroundTruth::kNone);
  try {
    pairs.WithIgnoredPairs(Write("bad_ignore.csv", "query,match\nz.jpg,a.jpg\n"), names_);
    FAIL() << "accepted an unknown image";
  } catch (const InputError& error) {
    EXPECT_EQ(error.path(), dir_.File("bad_ignore.csv"));
  }
}

// A data set folder: the image first (its ignored band is in it), then the pairs with their
// ignored pairs, then a .mat file; a folder with none of them is refused, naming the folder.
TEST_F(GroundTruthTest, DatasetFolderPicksItsGroundTruth) {
  const std::filesystem::path folder = dir_.path() / "set";
  std::filesystem::create_directories(folder);
  const auto touch = [&](const char* name) {
    std::ofstream(folder / name) << "x";
    return (folder / name).string();
  };
  try {
    GroundTruth::DatasetFiles(folder.string());
    FAIL() << "an empty folder gave ground truth";
  } catch (const InputError& error) {
    EXPECT_EQ(error.path(), folder.string());
    EXPECT_NE(std::string(error.what()).find("no ground truth in this folder"), std::string::npos);
  }
  const std::string mat = touch("ground_truth.mat");
  EXPECT_EQ(GroundTruth::DatasetFiles(folder.string()), std::vector<std::string>{mat});
  const std::string pairs = touch("ground_truth_pairs.csv");
  EXPECT_EQ(GroundTruth::DatasetFiles(folder.string()), std::vector<std::string>{pairs});
  const std::string ignore = touch("ground_truth_ignore.csv");
  EXPECT_EQ(GroundTruth::DatasetFiles(folder.string()), (std::vector<std::string>{pairs, ignore}));
  const std::string image = touch("ground_truth.bmp");
  EXPECT_EQ(GroundTruth::DatasetFiles(folder.string()), std::vector<std::string>{image});
}

TEST_F(GroundTruthTest, TextMatrix) {
  ExpectExample(GroundTruth::Load(Write("gt.txt", "0 0 0 0\n0 0 0 0\n1 0 0 0\n0.5 1 0 0\n"),
                                  GroundTruthFormat::kAuto, names_, 4),
                true);
}

TEST_F(GroundTruthTest, MatlabFile) {
  const std::string path = dir_.File("gt.mat");
  double values[16] = {0};  // column-major
  values[0 * 4 + 2] = 1;    // (2, 0)
  values[1 * 4 + 3] = 1;    // (3, 1)
  values[0 * 4 + 3] = 0.5;  // (3, 0): ignored
  mat_t* file = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(file, nullptr);
  size_t dims[2] = {4, 4};
  matvar_t* text = Mat_VarCreate("note", MAT_C_CHAR, MAT_T_UINT8, 2,
                                 std::array<size_t, 2>{1, 2}.data(), (void*)"hi", 0);
  Mat_VarWrite(file, text, MAT_COMPRESSION_NONE);
  Mat_VarFree(text);
  matvar_t* matrix = Mat_VarCreate("truth", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, values, 0);
  Mat_VarWrite(file, matrix, MAT_COMPRESSION_NONE);
  Mat_VarFree(matrix);
  Mat_Close(file);
  ExpectExample(GroundTruth::Load(path, GroundTruthFormat::kAuto, names_, 4), true);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes a 4x4 double matrix (or `side` x `side`) as variable "truth" of a v5 .mat file.
std::string WriteMat(const std::string& path, matio_compression compression, size_t side = 4) {
  std::vector<double> values(side * side, 0.0);
  mat_t* file = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
  size_t dims[2] = {side, side};
  matvar_t* matrix = Mat_VarCreate("truth", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, values.data(), 0);
  Mat_VarWrite(file, matrix, compression);
  Mat_VarFree(matrix);
  Mat_Close(file);
  return path;
}

// libmatio reads a truncated matrix as zeros and allocates what a header declares: both are
// caught before any data is read.
TEST_F(GroundTruthTest, TruncatedOrOversizedMatFilesAreRefusedBeforeReading) {
  for (const auto compression : {MAT_COMPRESSION_NONE, MAT_COMPRESSION_ZLIB}) {
    const std::string path = WriteMat(dir_.File("cut.mat"), compression, 40);
    const auto size = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, size - 20);
    ExpectError(path, "the .mat file is truncated: variable 1 needs", 40);
  }
  // A matrix of 100,000 x 100,000 declared in a few hundred bytes: refused from its header.
  const std::string huge = WriteMat(dir_.File("huge.mat"), MAT_COMPRESSION_NONE);
  std::string bytes = ReadFile(huge);
  const std::string four(reinterpret_cast<const char*>(std::array<int32_t, 2>{4, 4}.data()), 8);
  const size_t at = bytes.find(four);
  ASSERT_NE(at, std::string::npos);
  const std::array<int32_t, 2> declared = {100000, 100000};
  bytes.replace(at, 8, reinterpret_cast<const char*>(declared.data()), 8);
  std::ofstream(huge, std::ios::binary | std::ios::trunc) << bytes;
  ExpectError(huge, "the ground truth is 100000x100000 but the run has 4 images");
  // Dimensions the run's, data too short for them: an element smaller than its matrix.
  const std::string short_data = WriteMat(dir_.File("short.mat"), MAT_COMPRESSION_NONE, 2);
  bytes = ReadFile(short_data);
  const std::string two(reinterpret_cast<const char*>(std::array<int32_t, 2>{2, 2}.data()), 8);
  const std::array<int32_t, 2> twenty = {20, 20};
  bytes.replace(bytes.find(two), 8, reinterpret_cast<const char*>(twenty.data()), 8);
  std::ofstream(short_data, std::ios::binary | std::ios::trunc) << bytes;
  ExpectError(short_data, "declares 20x20 values but holds", 20);
}

TEST_F(GroundTruthTest, MalformedGroundTruthIsRefusedWithTheReason) {
  cv::imwrite(dir_.File("wide.png"), cv::Mat(4, 5, CV_8U, cv::Scalar(0)));
  ExpectError(dir_.File("wide.png"), "4x5, not square");
  cv::imwrite(dir_.File("color.png"), cv::Mat(4, 4, CV_8UC3, cv::Scalar(0)));
  ExpectError(dir_.File("color.png"), "8-bit grayscale");
  ExpectError(Write("broken.png", "not a png"), "cannot be read as an image");
  ExpectError(dir_.File("absent.csv"), "cannot be read");
  ExpectError(Write("ragged.txt", "0 0 0 0\n0 0 0\n"), "line 2 has 3 values, line 1 has 4");
  ExpectError(Write("words.txt", "0 0 x 0\n"), "line 1: 'x' is not a number");
  ExpectError(Write("nonsquare.txt", "0 0 0 0\n0 0 0 0\n"), "2x4, not square");
  ExpectError(Write("unknown.csv", "query,match\ne.jpg,a.jpg\n"),
              "line 2: 'e.jpg' is neither an image of the run nor an index");
  ExpectError(Write("range.csv", "9,0\n"), "image index 9 is outside the run's 4 images");
  ExpectError(Write("three.csv", "1,0,2\n"), "line 1: expected query,match");
  ExpectError(Write("notmat.mat", "MATLAB? no"), "cannot be read as a MATLAB .mat file");
  cv::imwrite(dir_.File("small.png"), cv::Mat(3, 3, CV_8U, cv::Scalar(0)));
  ExpectError(dir_.File("small.png"), "the ground truth is 3x3 but the run has 4 images");
  EXPECT_THROW(GroundTruth::ParseFormat("xml"), InputError);
  EXPECT_EQ(GroundTruth::ParseFormat("pairs"), GroundTruthFormat::kPairs);
}

}  // namespace
}  // namespace memloop
