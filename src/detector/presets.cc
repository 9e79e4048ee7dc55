#include "memloop/errors.h"
#include "memloop/options.h"

namespace memloop {

Options Options::Paper2011() {
  Options options;
  options.features.surf_upright = 0;
  options.features.sift_upright = 0;  // oriented, as the paper's SURF
  options.features.orb_upright = 0;
  options.features.min_image_side = 0;
  options.features.surf_rolled_view_degrees = 0;  // one view per image (and oriented SURF)
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
  options.memory.retrieved_kept_last_iterations = 0;
  options.memory.appearance_retrieval = 0;
  options.memory.retrieval_within_time = 0;
  options.memory.signature_within_time = 0;
  options.memory.signature_room_for_retrieval = 0;
  options.memory.retrieval_over_iterations = 0;
  options.memory.retrieval_stage_deferred = 0;
  options.memory.retrieval_kd_checks = 0;  // the dictionary's, as the 2011 code
  options.memory.retrieval_read_ahead = 0;
  options.memory.retrieval_min_value = 0;
  options.memory.retrieval_strong_value = 0;
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
  options.filter.support_from_image = 0;  // III-B: the merged words alone
  options.filter.min_shared_words = 1;    // the 2011 code: the hypothesis' own score > 0
  options.filter.ltm_neighbour_check = 0;
  options.verification.min_inliers = 0;  // no verification: T_loop alone accepts
  options.verification.loop_threshold = 0;
  options.verification.max_false_alarms = 0;
  options.verification.previous_agrees = 0;
  options.verification.correspondences = "words";
  options.verification.max_roll_degrees = 0;
  return options;
}

Options Options::HandHeld() {
  Options options;
  // U-SURF in the frame of each image's roll, from its edges (camera_roll.h), when the edges are
  // clear (strength 0.1, the default: a blurred 160x120 corridor's are not) and the roll is over
  // what U-SURF tolerates by itself (8 degrees).
  options.features.surf_max_roll_degrees = 45;
  options.features.surf_min_roll_degrees = 8;
  options.features.surf_min_roll_strength = 0.1;
  // Every image rolled 8-45 degrees is described in its rolled frame: no second view to add.
  options.features.surf_rolled_view_degrees = 0;
  // Rolled views then look alike however far apart they were rolled; by their shared words'
  // geometry (view_roll.h), those rolled more than 20 degrees apart are other views. Measured on
  // tum_fr1_rpy: bounds 15-35 give no false positive without a WM budget, 45 or none three; at
  // a quarter of WM, 25 and 30 give 13 (views 22-25 degrees apart), 18-22 none. lip6_outdoor's
  // strict / lenient recall: 52.8% / 84.1% at 15, 53.8% / 85.0% at 20, 58.8% / 94.0% at 30
  // (docs/design.md, "Camera roll").
  options.verification.max_roll_degrees = 20;
  // An image merged into older words (Rehearsal) keeps a loop closure but does not start one: the
  // filter has observed those words already (docs/design.md; measured: the false positive at
  // tum_fr1_rpy WM 13 removed, gp_walk_a under budgets 88% / 86% -> 91% / 91%).
  options.filter.cap_merged_images = 1;
  return options;
}

Options Options::DayNight() {
  Options options;
  // The whole-image channel beside the words (whole_image_likelihood.h; docs/design.md,
  // "Whole-image channel").
  options.features.whole_image = 1;
  return options;
}

Options Options::Verified() {
  Options options;
  // Between T_verified and T_loop, the hypotheses whose geometry chance would not give (fewer
  // than 1 false alarm on the image's keypoints matched by descriptor) and whose previous image's
  // hypothesis near L_i was a loop closure or verified (docs/design.md, "Verification under
  // T_loop"; at T_loop: gp_walk_a 63% -> 80%, corridor 9.9% -> 18.0%, no false positive). Not the
  // default: a camera turning about one spot sees one scene from views any epipolar geometry
  // fits (a rotation leaves the fundamental matrix undetermined), and tum_fr1_rpy's ground truth
  // calls views turned over 25 degrees other places (SIFT, ORB: 1-2 false positives).
  options.verification.min_inliers = 8;
  options.verification.loop_threshold = 0.05;
  options.verification.max_false_alarms = 1;
  options.verification.previous_agrees = 2;
  options.verification.correspondences = "descriptors";
  return options;
}

Options Preset(const std::string& name) {
  if (name == "default") return Options();
  if (name == "paper2011") return Options::Paper2011();
  if (name == "hand-held") return Options::HandHeld();
  if (name == "day-night") return Options::DayNight();
  if (name == "verified") return Options::Verified();
  throw ParameterError("--preset", "unknown preset '" + name +
                                       "' (default, paper2011, hand-held, day-night or verified)");
}

}  // namespace memloop
