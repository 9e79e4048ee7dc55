// Loop-closure ground truth: a square matrix over the images of a sequence (row and column i =
// the i-th image in processing order), read from any of the forms data sets come in:
// - a MATLAB .mat file holding a square 0/1 matrix (the community data sets), read with libmatio;
// - a square 8-bit grayscale image (.bmp, .png, .pgm, ...): 255 = loop, 0 = none, any other value
//   = ignored (RTAB-Map's form);
// - a CSV of pairs "query,match", by image file name or by 0-based image index;
// - a whitespace-separated text matrix of 0/1 (other values: ignored).
// Pairs are symmetric: (a, b) and (b, a) are the same place.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "memloop/types.h"

namespace memloop {

enum class GroundTruthFormat { kAuto, kMat, kImage, kPairs, kMatrix };

class GroundTruth {
 public:
  enum Label : unsigned char { kNone = 0, kLoop = 1, kIgnored = 2 };

  // Reads `path`; kAuto picks the form from the extension (.mat; .csv; .txt/.dat/.gt; an image
  // otherwise). `image_names` names the images by index, for pairs given by name. Throws
  // InputError naming the file and the problem: unreadable, not square, malformed line N,
  // unknown image name, index out of range, no matrix in a .mat file.
  static GroundTruth Load(const std::string& path, GroundTruthFormat format,
                          const std::vector<std::string>& image_names, int image_count);
  // A data set folder as memloop's data sets come: ground_truth.bmp (or .png: its ignored band
  // included), else ground_truth_pairs.csv with ground_truth_ignore.csv when there is one, else
  // ground_truth.mat. Returns the files to read, the ignored pairs' CSV second when there is one.
  // Throws InputError naming the folder when it holds none of them.
  static std::vector<std::string> DatasetFiles(const std::string& folder);
  // "auto", "mat", "image", "pairs", "matrix"; throws InputError otherwise.
  static GroundTruthFormat ParseFormat(const std::string& name);
  // `labels`: square CV_8U of Label values, made symmetric here.
  explicit GroundTruth(const cv::Mat& labels);

  int size() const { return labels_.rows; }
  Label At(ImageIndex a, ImageIndex b) const;
  bool IsLoop(ImageIndex a, ImageIndex b) const { return At(a, b) == kLoop; }
  // True when `query` shows the same place as an earlier image.
  bool HasEarlierMatch(ImageIndex query) const;
  int PairCount() const;  // loop pairs (a > b)
  // The protocol of the paper's own 2011 scripts (`memloop eval --ignored-as-true`): for an image
  // with a true earlier match, its ignored earlier pairs become loops, so a detection within the
  // ignored band counts as found. Images without a true earlier match are left as they are (on
  // tum_fr1_rpy, whose ignored pairs include neighbouring frames, making those loops would count
  // nearly every image as one with a loop), so the images with a loop are the same.
  GroundTruth IgnoredAsLoops() const;
  // The pairs listed in `path` (a CSV of pairs, as for Load) become ignored, neither true nor
  // false, unless they are loops: what a CSV of loop pairs cannot say by itself.
  GroundTruth WithIgnoredPairs(const std::string& path,
                               const std::vector<std::string>& image_names) const;

 private:
  cv::Mat labels_;
};

}  // namespace memloop
