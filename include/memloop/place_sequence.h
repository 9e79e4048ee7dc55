// A generated sequence of any length, for measuring scale (issue 9): the camera walks past
// distinct places, one after another, and on a schedule comes back to a place seen long before,
// so that only retrieval from LTM can find it. Every place is a textured strip of its own, drawn
// from the seed and its number, so the sequence needs no more memory than one place; frames carry
// the same small changes of viewpoint and exposure as the demo route.
#pragma once

#include <functional>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "memloop/generated_layout.h"

namespace memloop {

struct PlaceSequenceOptions {
  int seed = 7;
  int places = 100;           // distinct places
  int frames_per_place = 10;  // frames of each visit, the camera moving step_px between them
  // After every `revisit_every` new places, one revisit of an earlier place (0: none), chosen at
  // random among those last seen at least `min_revisit_age` images before.
  int revisit_every = 10;
  int min_revisit_age = 1000;
  int image_width = 320;
  int image_height = 240;
  double step_px = 160;
  // Frames of two visits of a place show the same place when their views are this close (as the
  // demo route: 0.6 of the image width).
  double same_place_fraction = 0.6;
};

class PlaceSequence {
 public:
  // Throws InputError when an option is out of range.
  explicit PlaceSequence(const PlaceSequenceOptions& options);

  int size() const { return static_cast<int>(frames_.size()); }
  // Frame `index` (0-based), 8-bit BGR. Fastest in order (the current place is kept).
  cv::Mat Render(int index) const;
  // True when frame `query` shows the same place as the earlier frame `match` of another visit.
  bool IsLoop(int query, int match) const;
  // Every (query, match) with match < query and IsLoop(query, match).
  std::vector<std::pair<int, int>> GroundTruthPairs() const;
  // Frames of revisits (each has a loop), and revisits.
  int revisit_frames() const;
  int revisits() const { return revisits_; }
  // Writes images/1.png .. images/N.png and ground_truth_pairs.csv, as SyntheticRoute::Write.
  void Write(const std::string& folder, const std::function<void(int)>& written = {},
             GeneratedLayout layout = GeneratedLayout::kImages) const;

 private:
  struct Frame {
    int place;
    int visit;   // visits of the sequence, in order
    int offset;  // frame within the visit
    double dx, dy, scale, angle_degrees, gain, bias;
  };
  cv::Mat PlaceTexture(int place) const;

  PlaceSequenceOptions options_;
  std::vector<Frame> frames_;
  std::vector<std::vector<int>> visits_of_place_;  // first frame of each visit, in order
  int revisits_ = 0;
  mutable std::mutex cache_mutex_;
  mutable int cached_place_ = -1;
  mutable cv::Mat cached_texture_;
};

}  // namespace memloop
