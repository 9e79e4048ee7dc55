#include "memloop/errors.h"
#include "memloop/options.h"

namespace memloop {

Options Options::Paper2011() {
  Options options;
  options.features.surf_upright = 0;
  options.features.sift_upright = 0;  // oriented, as the paper's SURF
  options.features.orb_upright = 0;
  options.features.min_image_side = 0;
  // The 2011 code's SURF (OpenCV 2.2): det(H) >= 100, 4 octaves of 2 layers (4 filter sizes), the
  // first octave sampled at every pixel. The text says "SURF" only.
  options.features.surf_hessian_threshold = 100;
  options.features.surf_sample_step = 1;
  // The 2011 code's ratio test, 0.8 on FLANN's squared distances: sqrt(0.8) on distances, with
  // 64 leaves checked (Kp/NndrRatio, Kp/MaxLeafs).
  options.dictionary.nndr_ratio = 0.894427191;
  options.dictionary.kd_checks = 64;
  options.memory.rehearsal_most_similar = 1;        // Memory::rehearsal
  options.memory.retrieved_immune_iterations = 10;  // Mem/DelayRequired
  options.memory.stm_size = 25;
  options.memory.protect_hypothesis = 0;
  options.memory.appearance_retrieval = 0;
  options.memory.retrieval_within_time = 0;
  options.memory.retrieval_read_ahead = 0;
  options.memory.retrieval_min_value = 0;
  options.memory.time_target = 1.0;
  options.memory.transfer_max_fraction = 0;
  options.memory.wm_min_time_share = 0;
  options.memory.max_dictionary_words = 0;
  options.filter.hypothesis_value = "best_neighbours";  // Rtabmap::selectHypotheses
  options.filter.loop_threshold = 0.10;
  options.filter.loop_ratio = 0.9;             // Rtabmap/LoopRatio
  options.filter.no_signal_virtual_place = 2;  // Rtabmap::adjustLikelihood
  options.filter.min_sigma_ratio = 0;          // eq. 3-4 as written
  options.filter.likelihood = "similarity";
  options.filter.require_support = 0;
  options.filter.min_shared_words = 1;  // the 2011 code: the hypothesis' own score > 0
  options.filter.ltm_neighbour_check = 0;
  options.verification.min_inliers = 0;
  return options;
}

Options Preset(const std::string& name) {
  if (name == "default") return Options();
  if (name == "paper2011") return Options::Paper2011();
  throw ParameterError("--preset", "unknown preset '" + name + "' (default or paper2011)");
}

}  // namespace memloop
