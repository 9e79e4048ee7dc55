// The two images of each loop closure side by side, as thumbnails inlined in the report's page
// (`memloop report --images FOLDER_OR_VIDEO`): what the detector matched, to be seen.
#pragma once

#include <string>
#include <vector>

#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"
#include "memloop/types.h"

namespace memloop {

struct LoopClosureView {
  ImageIndex query = kNoImage;
  ImageIndex match = kNoImage;  // the matched location's image shown (the true one if any)
  double probability = 0;       // the hypothesis value that accepted it
  std::string verdict;          // "true", "false" or "ignored" against ground truth; "" without
};

// Every loop closure the run accepted, judged as `memloop eval` judges it (memloop::Judge) when
// `truth` is given: the report's figure and its views draw these, so they agree with eval.
std::vector<LoopClosureView> AcceptedLoopClosures(const std::vector<RunRow>& rows,
                                                  const GroundTruth* truth);

// An HTML section with one row per view, false positives first, then ignored, then true ones,
// at most `max_views` (spread evenly over each verdict's list when there are more). `images` is
// the folder or video the run read; images are found by the names in `rows` (a folder's files, a
// video's "frame N", its frame number also when the run sampled it with --rate), each thumbnail's
// alt text "image I (NAME)". Throws InputError naming `images` when it is not the run's sequence.
std::string LoopClosureViewsSection(const std::vector<LoopClosureView>& views,
                                    const std::vector<RunRow>& rows, const std::string& images,
                                    int max_views);

// The views to show, in order, from `views` (exposed for its test).
std::vector<LoopClosureView> ChooseViews(const std::vector<LoopClosureView>& views, int max_views);

}  // namespace memloop
