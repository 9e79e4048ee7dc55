// The report's ground-truth matrix (query x earlier match) with the run's loop closures and
// misses, drawn as SVG by memloop itself so that each point links to its image pair's row.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "eval/loop_closure_views.h"
#include "memloop/ground_truth.h"

namespace memloop {

// Grey: ground-truth pairs; green: true positives; purple: on an ignored pair; red: false
// positives; orange: misses (at the query's true match). A point whose query is in `listed` links
// to "#pair-QUERY" and names its images in a tooltip. `names`: the run's image names by index.
std::string GroundTruthSvg(const GroundTruth& truth, const std::vector<LoopClosureView>& views,
                           const std::set<ImageIndex>& listed,
                           const std::vector<std::string>& names);

}  // namespace memloop
