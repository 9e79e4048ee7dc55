// Options of every component, one struct each (Ceres style). Defaults are the paper's values
// (Labbe & Michaud, IROS 2011, Sec. IV) where the paper gives one. Each field is described,
// with unit and range, in the parameter registry (params.h), which is the single source of
// `memloop params`, `--set NAME=VALUE`, validation and docs/parameters.md.
#pragma once

#include <string>

namespace memloop {

struct FeatureOptions {
  // Feature backend: "surf" (memloop's SURF, the paper's), "sift" or "orb" (OpenCV).
  std::string type = "surf";
  // Keep at most this many strongest keypoints per image (0 = all).
  int max_features = 400;

  // SURF (Bay et al. 2008): octaves, intervals and step as in the SURF paper.
  // det(H) of 0-255 intensities. Low, so that the max_features strongest decide, as the paper-era
  // "400 strongest" does: docs/surf.md has the measurements behind it.
  double surf_hessian_threshold = 50;
  int surf_octaves = 4;
  int surf_intervals = 4;
  int surf_sample_step = 2;  // pixels, first octave; doubled per octave
  int surf_extended = 0;     // 1: 128-d descriptors
  int surf_upright = 0;      // 1: U-SURF, no orientation
};

struct DictionaryOptions {
  // Nearest-neighbour distance ratio: a descriptor joins its nearest word only when
  // d1 < ratio * d2 on true (not squared) L2 distances; otherwise it becomes a new word.
  double nndr_ratio = 0.8;
  // Randomized kd-trees in the forest (FLANN KDTreeIndex).
  int kd_trees = 4;
  // Leaves visited per search (FLANN "checks"): more is slower and closer to exact.
  int kd_checks = 32;
  // The forest is rebuilt when points added and removed since the last build exceed this
  // fraction of its size at that build; otherwise it is updated incrementally.
  double rebuild_fraction = 1.0;
  // Seed of the forest's random split choice, so runs repeat exactly.
  int seed = 42;
  // Binary descriptors (ORB) are indexed by locality-sensitive hashing (FLANN LshIndex):
  // hash tables, bits per hash key, and neighbouring buckets probed (FLANN's defaults).
  int lsh_tables = 12;
  int lsh_key_bits = 20;
  int lsh_probe_level = 2;
};

struct MemoryOptions {
  // STM size: the newest locations, excluded from loop closure detection (paper III).
  int stm_size = 25;
  // T_rehearsal: similarity (eq. 1) above which L_c is merged into L_t (paper III-B).
  double rehearsal_threshold = 0.20;
  // T_time in milliseconds: iteration time above which locations are transferred from WM to LTM
  // (paper III-F). The paper's guideline is 200-400 ms under the image period: 700 ms at 1 Hz.
  // 0 disables the time limit (T_time = infinity); the result then depends on the machine's
  // speed, so repeatable runs use the budgets below instead.
  double time_limit_ms = 700.0;
  // Deterministic budget: transfer while WM holds more locations than this (0 = no budget).
  int max_wm_locations = 0;
  // Deterministic budget: transfer while the dictionary holds more words than this (0 = none).
  int max_dictionary_words = 0;
  // At most this many locations retrieved from LTM per iteration (paper III-E: two).
  int max_retrieved = 2;
  // A resume checkpoint every this many images (checkpoint.h). A crash loses at most
  // 2 * checkpoint_interval images: the last committed checkpoint is at most one behind.
  int checkpoint_interval = 1;
};

struct FilterOptions {
  // T_loop: a neighbour-summed hypothesis above this is accepted as a loop closure (III-D).
  double loop_threshold = 0.10;
  // T_minHyp: no loop closure is accepted while WM holds fewer locations (III-D).
  int min_hypotheses = 15;
  // p(S_t=-1 | S_t-1=-1): probability that a new location follows a new location (III-C, 1).
  double virtual_place_stay = 0.9;
  // Links away from j over which p(S_t=i | S_t-1=j) is non-null (III-C, 4): four.
  int neighbour_range = 4;
  // Standard deviation, in links, of the discretized Gaussian of the transition model.
  double neighbour_sigma = 1.6;
  // Eq. 3-4: sigma is taken as at least this fraction of mu, so that p(L_t | S_t = -1) =
  // mu/sigma + 1 is continuous as sigma -> 0 (at most 1/ratio + 1 = 51). 0: the paper as written
  // (sigma = 0 gives 2, near ties give any value). docs/design.md has the measurements.
  double min_sigma_ratio = 0.02;
};

struct Options {
  FeatureOptions features;
  DictionaryOptions dictionary;
  MemoryOptions memory;
  FilterOptions filter;
};

}  // namespace memloop
