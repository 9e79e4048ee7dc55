#include "memloop/errors.h"
#include "memloop/options.h"

namespace memloop {

Options Options::Paper2011() {
  Options options;
  options.features.surf_upright = 0;
  options.features.sift_upright = 0;  // oriented, as the paper's SURF
  options.features.orb_upright = 0;
  options.features.min_image_side = 0;
  options.memory.stm_size = 25;
  options.memory.protect_hypothesis = 0;
  options.memory.appearance_retrieval = 0;
  options.memory.retrieval_within_time = 0;
  options.memory.retrieval_read_ahead = 0;
  options.memory.retrieval_min_value = 0;
  options.memory.time_target = 1.0;
  options.memory.transfer_max_fraction = 0;
  options.memory.max_dictionary_words = 0;
  options.filter.hypothesis_value = "neighbours";
  options.filter.loop_threshold = 0.10;
  options.filter.likelihood = "similarity";
  options.filter.require_support = 0;
  options.filter.min_shared_words = 0;
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
