// The report's image pairs: each loop closure the run accepted and each one it missed, by file
// name, with its images side by side when the run's images are given (thumbnails inlined in the
// page, `memloop report --images FOLDER_OR_VIDEO`): what the detector matched, to be seen.
#pragma once

#include <string>
#include <vector>

#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"
#include "memloop/types.h"

namespace memloop {

struct LoopClosureView {
  ImageIndex query = kNoImage;
  // The place the run chose: the matched location's image shown (the true one if any); for a
  // miss, the image of its highest hypothesis (kNoImage: the virtual place, nothing earlier).
  ImageIndex match = kNoImage;
  double probability = 0;  // that hypothesis' value
  // "true", "false" or "ignored" against ground truth, "missed" for an image with a true earlier
  // match and no loop closure accepted; "" without ground truth.
  std::string verdict;
  ImageIndex true_match = kNoImage;  // for a false positive or a miss: the query's true match
};

// Every loop closure the run accepted, judged as `memloop eval` judges it (memloop::Judge) when
// `truth` is given: the report's figure and its views draw these, so they agree with eval.
std::vector<LoopClosureView> AcceptedLoopClosures(const std::vector<RunRow>& rows,
                                                  const GroundTruth* truth);
// Every image with a true earlier match for which the run accepted no loop closure, with what its
// highest hypothesis chose instead and the most recent true match.
std::vector<LoopClosureView> MissedLoopClosures(const std::vector<RunRow>& rows,
                                                const GroundTruth& truth);

// An HTML section with one row per view (id "pair-QUERY", what the figures link to), false
// positives first, then misses, ignored and true ones, at most kMaxListedViews. With `images`
// (the folder or video the run read), `max_views` of the rows (in the same order, spread evenly
// over a verdict's list when it does not fit) show the query, the chosen image and the true
// match as thumbnails. Images are found by the names in `rows` (a folder's files, a video's
// "frame N", its frame number also when the run sampled it with --rate), each thumbnail's alt text
// "image I (NAME)". Throws InputError naming `images` when it is not the run's sequence.
std::string LoopClosureViewsSection(const std::vector<LoopClosureView>& views,
                                    const std::vector<RunRow>& rows, const std::string& images,
                                    int max_views);
constexpr int kMaxListedViews = 2000;

// The views to show, in order, from `views` (exposed for its test).
std::vector<LoopClosureView> ChooseViews(const std::vector<LoopClosureView>& views, int max_views);

}  // namespace memloop
