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
  // Images whose smaller side is under this many pixels are enlarged (bilinear, by the smallest
  // integer factor that reaches it) before extraction; keypoints are given in the image's own
  // pixels (memloop: at 160x120 the detectors find too few features; docs/real-data.md). 0: as
  // they are (the paper).
  int min_image_side = 240;

  // SURF (Bay et al. 2008): octaves, intervals and step as in the SURF paper.
  // det(H) of 0-255 intensities. Low, so that the max_features strongest decide, as the paper-era
  // "400 strongest" does: docs/surf.md has the measurements behind it.
  double surf_hessian_threshold = 50;
  int surf_octaves = 4;
  int surf_intervals = 4;
  int surf_sample_step = 2;  // pixels, first octave; doubled per octave
  int surf_extended = 0;     // 1: 128-d descriptors
  // 1: U-SURF, no orientation (memloop's default: a robot's camera does not roll, and rolled views
  // of one spot are not the same place; the paper's SURF is 0). docs/real-data.md measures it.
  int surf_upright = 1;
  // U-SURF: when the image's edges say the camera is rolled (camera_roll.h) by at most this many
  // degrees, every keypoint is described in the rolled frame instead of at angle 0 (0: off).
  double surf_max_roll_degrees = 0;
  double surf_min_roll_strength = 0.1;  // the roll estimate's strength needed (0..1)
  double surf_min_roll_degrees = 10;    // smaller rolls are left to U-SURF's own tolerance
  // U-SURF: when the image's edges say the camera is rolled by at most this many degrees (and by
  // surf.min_roll_degrees or more), its keypoints are also described in the rolled frame, a
  // second view matched against WM beside the upright one (detector/rolled_view.h; 0: off).
  double surf_rolled_view_degrees = 20;
  // The same for OpenCV's SIFT and ORB: 1 describes every keypoint at angle 0 (memloop; OpenCV's
  // own detectors orient them, as Options::Paper2011() keeps). On the hand-held tum_fr1_rpy,
  // oriented SIFT and ORB match rolled views the ground truth calls different (docs/real-data.md).
  int sift_upright = 1;
  int orb_upright = 1;
  // 1: each location also keeps a whole-image descriptor (HOG of a thumbnail, 756 bytes), which
  // the filter weighs beside the words (filter.whole_image_gain): places seen by day are found
  // by night (memloop, issue 34; docs/design.md, "Whole-image channel"). 0: the words alone.
  int whole_image = 0;
};

struct DictionaryOptions {
  // Nearest-neighbour distance ratio: a descriptor joins its nearest word only when
  // d1 < ratio * d2 on true (not squared) L2 distances; otherwise it becomes a new word.
  double nndr_ratio = 0.8;
  // Randomized kd-trees in the forest (FLANN KDTreeIndex).
  int kd_trees = 4;
  // Leaves visited per search (FLANN "checks"): more is slower and closer to exact.
  int kd_checks = 32;
  // Threads searching the dictionary, the caller's included: an image's descriptors (and a
  // retrieved location's words) are shared between them. Each descriptor's answer is the same
  // whatever the number, so results are too; only the time changes.
  int search_threads = 2;
  // The forest is rebuilt when points added and removed since the last build exceed this
  // fraction of its size at that build; otherwise it is updated incrementally.
  double rebuild_fraction = 1.0;
  // Insertions (about one per image) between the start of a full rebuild and its use. The new
  // forest is built in a background thread from a snapshot of the words, so no iteration pays for
  // it; it replaces the old one, brought up to date, this many insertions later (or one per
  // 10,000 words of the snapshot, if more; waiting for the build if it is not done), so the same
  // images give the same words. 0: rebuilt inside the
  // iteration that crosses rebuild_fraction (a stop-the-world pause, as memloop did before).
  int rebuild_delay = 30;
  // Not a parameter: the Detector sets it when T_time is on. The new forest is used at the same
  // insertion as with T_time off when it is built by then (waited for while the iteration has
  // time to spare: WordIndex::SetSwapWait), else at the first insertion after it is built.
  bool rebuild_swap_when_ready = false;
  // Seed of the forest's random split choice, so runs repeat exactly.
  int seed = 42;
  // Binary descriptors (ORB) are indexed by locality-sensitive hashing (FLANN LshIndex):
  // hash tables, bits per hash key, and neighbouring buckets probed (FLANN's defaults).
  int lsh_tables = 12;
  int lsh_key_bits = 20;
  int lsh_probe_level = 2;
};

struct MemoryOptions {
  // STM size: the newest locations, excluded from loop closure detection (paper III; 25 in
  // Options::Paper2011()).
  int stm_size = 20;
  // T_rehearsal: similarity (eq. 1) above which L_c is merged into L_t (paper III-B).
  double rehearsal_threshold = 0.20;
  // 0: L_t is compared with STM from the newest location back and merged with the first above
  // T_rehearsal (the paper's text, III-B). 1: compared with every STM location and merged with the
  // most similar, if above T_rehearsal (the paper's 2011 code, Memory::rehearsal).
  int rehearsal_most_similar = 0;
  // T_time in milliseconds: iteration time above which locations are transferred from WM to LTM
  // (paper III-F). The paper's guideline is 200-400 ms under the image period: 700 ms at 1 Hz.
  // 0 disables the time limit (T_time = infinity); the result then depends on the machine's
  // speed, so repeatable runs use the budgets below instead.
  double time_limit_ms = 700.0;
  // Transfer starts when the iteration, counted up to the transfer step (the previous image's
  // checkpoint, written at its start, included), reaches this fraction of T_time (the paper: 1.0).
  // Below 1, WM settles where the iteration takes this fraction of T_time, so that one over T_time
  // is the exception rather than half of them (issue 9, docs/scale.md).
  double time_target = 0.75;
  // When an iteration is over the time target, transfer enough WM locations for the next one to
  // fit (the WM-dependent stages scaled to what the target leaves), at most this fraction of WM
  // per iteration (memloop). 0: the paper's rule alone, words transferred = words added, about
  // one location per iteration, which takes thousands of images to bring an overgrown WM back.
  double transfer_max_fraction = 0.02;
  // Over the time target, WM's own stages (likelihood, filter, selection) may take what the other
  // stages leave of the target, and at least this share of it: only WM beyond that is
  // transferred for time, since a smaller WM cannot make up for slow features or retrieval
  // (memloop, issue 37). 0: the paper, every iteration over the target transfers.
  double wm_min_time_share = 0.25;
  // 1 (with T_time on): an image's features are quantized strongest first, and quantization stops
  // between chunks of the search once the iteration, with what its later steps are expected to
  // take, would pass the time target; the weaker features left are dropped (memloop, issue 37:
  // the kd-forest search is most of an iteration, and takes twice as long when the search's
  // second thread finds the other core busy). 0: every feature, whatever the time (the paper).
  int signature_within_time = 1;
  // Of an image's features, at least this share (the strongest) is quantized, however late.
  double signature_min_share = 0.5;
  // 1 (with signature_within_time and T_time on): after an iteration that deferred a retrieval
  // for lack of time, the next image's quantization also stops early enough for the deferred
  // locations (and the transfer after them) to fit under T_time (memloop, issue 37: under a tight
  // T_time the place recognized came back one image late, after the robot had moved on).
  int signature_room_for_retrieval = 1;
  // With signature_within_time: when an image's features would not all be quantized by the time
  // target, their search first visits fewer leaves than dictionary.kd_checks, in proportion to
  // the time left, down to this many; only then are features dropped. 0: always the
  // dictionary's (features dropped first).
  int signature_min_checks = 8;
  // With signature_within_time and T_time on: the share of iterations that may pass T_time. The
  // quantization's deadline adapts to it (memloop, issue 37: on a machine other programs load,
  // an iteration's time varies more than its steps' estimates say): each iteration over T_time
  // brings it 10% of the time target earlier, each within moves it back by that x goal / (1 -
  // goal), so that over T_time the share of iterations over it is the goal; never later than the
  // time target, never earlier than half of it. 0: the time target alone.
  double over_time_goal = 0.005;
  // Deterministic budget: transfer while WM holds more locations than this (0 = no budget).
  int max_wm_locations = 0;
  // Deterministic budget: transfer while the dictionary holds more words than this (0 = none).
  // memloop bounds memory by default (about 1.7 KB per word, forest and descriptors included),
  // which T_time alone does not: a WM that fit T_time grew to 1.07 million words and 2.0 GB over
  // 50,000 images (issue 9). 100,000 is the size the paper's own runs reached under T_time (its
  // Table I: 99,000-106,000 words); against 400,000, a 50,000-image run at T_time 67 ms kept a
  // flat median (1.15x from images 1,000-2,000, 1.55x), half the memory (464 vs 908 MB) and found
  // more revisits (75% vs 73%); the real data sets stay below it (at most 47,000 words:
  // unchanged). docs/scale.md. The paper has no such bound: 0.
  int max_dictionary_words = 100000;
  // At most this many locations retrieved from LTM per iteration (paper III-E: two).
  int max_retrieved = 2;
  // A retrieved location is not transferred during this many iterations, the retrieving one
  // included (III-F: "the retrieved locations of the current iteration": 1). The paper's 2011
  // code waited 10 (Mem/DelayRequired): by weight and age, a retrieved old location would
  // otherwise be the first to leave again at the next iteration.
  int retrieved_immune_iterations = 1;
  // During this many iterations, the retrieving one included, a retrieved location leaves WM
  // only after all the others (as the highest hypothesis' neighbourhood, protect_hypothesis), so
  // that the budgets still hold (memloop, issue 37: under T_time a location retrieved for a
  // revisit left again two images later, when a chance hypothesis was the highest, before the
  // filter had carried the revisit onto it; docs/design.md). 0: off (the paper).
  int retrieved_kept_last_iterations = 10;
  // The highest hypothesis' LTM neighbours are retrieved only when its value (the one compared
  // with T_loop) reaches this (memloop: below it the highest hypothesis is noise; over 50,000
  // images 91% of the retrieved locations were never matched and 81% came back at a value under
  // 0.01, each re-matching ~150 words; docs/design.md). 0: whatever the value (the paper, III-E).
  double retrieval_min_value = 0.02;
  // Under T_time, a highest hypothesis under this value is retrieved for only when its retrieval
  // is expected to end within the first half of T_time (a staged retrieval's cost falls on the
  // next iterations); at or over it, and with T_time off, as before (memloop, issue
  // 37: under a tight T_time most retrievals were of chance hypotheses just over
  // retrieval_min_value, and made the iterations over T_time; a threshold of 0.05 at every
  // iteration also cut retrievals under WM budgets, and cost recall on real data). 0: off.
  double retrieval_strong_value = 0.05;
  // 1 (with T_time on): a location is retrieved only when the iteration, with its expected
  // retrieval time, still ends under T_time; the others wait for a
  // later iteration (memloop, issue 9: re-matching one location's words costs about as much as
  // quantizing an image). 0: up to max_retrieved whatever the time (the paper).
  int retrieval_within_time = 1;
  // 1 (with T_time on and retrieval_within_time): a thread reads ahead the map-file rows of the
  // locations retrieval asks for and hands them over, brought up to date with the writes since;
  // a location is retrieved once they are read, waited for only as long as the iteration allows
  // (memloop, issue 9: a row not in the OS's cache took 50-150 ms to read inside an iteration).
  // 0: read when retrieved, whatever it takes (the paper).
  int retrieval_read_ahead = 1;
  // 1 (with the read-ahead): a location is readied for retrieval over as many iterations as it
  // takes: the words of it that left the dictionary are re-matched a chunk of the kd-forest
  // search at a time, while the iteration has room, and it comes back once they all are (memloop,
  // issue 37: re-matching a location at once costs about an image's quantization, which a tight
  // T_time rarely leaves, so retrievals were deferred and revisits lost). 0: a location is
  // retrieved whole in one iteration, or deferred.
  int retrieval_over_iterations = 1;
  // Under T_time, with retrieval_over_iterations: leaves the kd-forest search visits when
  // re-matching a staged location's words (III-E); 0: dictionary.kd_checks, as for an image's
  // features and as with T_time off. A word's twin (the same feature seen again) is close to it
  // and found early: 8 makes re-matching 4x cheaper where time is short (issue 37; docs/design.md,
  // "Fixed costs under a tight T_time").
  int retrieval_kd_checks = 8;
  // Under T_time, with retrieval_over_iterations: the neighbours of a place asked for that lie
  // ahead of it (the way the robot goes along the old route: newer locations when the places
  // recognized image after image grow newer) are asked for first, and their words that the
  // iteration has no room to search are not searched in the kd-forest: the robot has not been
  // there yet in this pass, so they have no twins to find; at their retrieval they are compared
  // with the words that joined since (Dictionary::MatchSince), and the others come back under
  // their old ids, as words that matched none do. Staging then searches the place the robot is
  // at, and WM holds the next places before the robot gets there (issue 37). 0: every staged word
  // is searched.
  int retrieval_ahead_unsearched = 1;
  // Under T_time, with retrieval_over_iterations: a location asked for whose words the iteration
  // has no room to search comes back at once, its words compared only with the words that joined
  // since the retrieval step this many images before (its twins: the words of the images that
  // recognize it, made while it was in LTM), instead of waiting until the kd-forest search
  // reaches them. Older twins are not looked for: such a word comes back under its old id beside
  // its twin. At most 31 (the marks RetrievalStaging keeps). -1: it waits until its words are
  // searched (places ahead excepted: retrieval_ahead_unsearched).
  int retrieval_recent_twins = 3;
  // Under T_time, with retrieval_over_iterations: a location asked for when no retrieval fits any
  // more in the iteration is staged all the same (its rows read ahead), so that the next extraction
  // searches its words and the next iterations carry it on. 0: it is asked for again only if a
  // later image asks (the place recognized again, or the hypothesis on it).
  int retrieval_stage_deferred = 1;
  // 1: retrieval by appearance (memloop): the LTM location that looks most like the image
  // (appearance_index.h) comes back into WM with its neighbours, at most max_retrieved, when its
  // score stands out of all LTM's by appearance_min_z standard deviations, so that a place whose
  // whole neighbourhood left WM can still be recognized. 0: only the highest hypothesis'
  // neighbours are retrieved (the paper, III-E).
  int appearance_retrieval = 1;
  // A fleet's map (a server map with --robot): places of other robots that join this robot's WM
  // per image (as retrieved places do), read from the server in the background (fleet_places.h).
  // Each costs about a quantization of an image's features. 0: other robots' places are not
  // searched.
  int fleet_imports = 4;
  // Entries of the fixed vocabulary that describes locations for retrieval by appearance: the
  // dictionary's first words, copied as they are created. 32,768 (8,192 until 2026-12-03): with
  // appearance_max_postings, the rarest entries still tell a million places apart
  // (bench/appearance_search_benchmark.cc: every revisit found at a million, against 31% with
  // 8,192); complete after ~160-200 images, its search index built in the background.
  int appearance_vocabulary = 32768;
  // How far (standard deviations over LTM's scores) the best LTM location must stand out to be
  // retrieved by appearance.
  double appearance_min_z = 8.0;
  // ... and at least this many times sqrt(2 ln N), how far the best of N chance scores stands out
  // (N: LTM's locations; AppearanceMinZ). With appearance_min_z alone, chance offers grew with
  // LTM: on generated new places, z >= 8 on 0.2% of images at LTM ~400 and 1.9% at LTM 26,000,
  // each a retrieval that finds nothing (its p99 is 1.9-2.0 sqrt(2 ln N) from 400 to 26,000). 0:
  // appearance_min_z alone (memloop until 2026-12-04).
  double appearance_chance_multiple = 2.5;
  // A search by appearance sums the image's rarest entries first, and stops before their
  // postings (LTM locations holding them) pass this many, so that its time stops growing with LTM
  // (BM_AppearanceBest, a million locations: 0.44 ms at 40,000 with the 32,768-entry vocabulary,
  // 1.6x its time at 25,000, against 8.4 ms for every entry; bench/scale.sh's 50,000 images:
  // median 1.17x from images 1,000-2,000 to the last 1,000, revisits 75.8%, docs/scale.md).
  // 0: every entry (memloop until 2026-12-03).
  int appearance_max_postings = 40000;
  // 1: the highest hypothesis' WM neighbourhood (with the locations retrieved for it) is
  // transferred only after every other WM location (memloop); 0: by weight and age like any
  // other (the paper).
  int protect_hypothesis = 1;
  // A resume checkpoint every this many images (checkpoint.h). A crash loses at most
  // 2 * checkpoint_interval images: the last committed checkpoint is at most one behind (with
  // T_time on, checkpoint_max_skipped images more).
  int checkpoint_interval = 1;
  // With T_time on, an image's checkpoint is skipped while the previous one is still being
  // committed, at most this many in a row (memloop, issue 9: the writer's disk flush stalled for
  // up to 580 ms); a crash then loses up to this many images more. 0: always waited for.
  int checkpoint_max_skipped = 100;
  // 1: localization (as RTAB-Map's): images are matched against an existing map, which they do
  // not join. The map file is opened read-only; retrieval and transfer still move locations
  // between WM and LTM, in memory only. 0: mapping, the paper.
  int localization = 0;
};

struct FilterOptions {
  // T_loop: a hypothesis whose value (hypothesis_value) exceeds this is a loop closure (III-D).
  // 0.11 (RTAB-Map's default) for memloop's loop_mass value; 0.10 in Options::Paper2011().
  double loop_threshold = 0.11;
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
  // Eq. 4 when no score stands out (no s_j >= mu + sigma, or sigma ~ 0): p(L_t | S_t = -1) is
  // set to this instead of mu/sigma + 1 (the paper's 2011 code, Rtabmap::adjustLikelihood: 2).
  // 0: eq. 4 as written whatever the scores.
  double no_signal_virtual_place = 0;
  // The hypothesis' value compared with T_loop (III-D): "neighbours", the posterior summed over
  // the highest hypothesis' neighbourhood (the paper), or "loop_mass", 1 - p(S_t = -1), the
  // probability that L_t closes a loop anywhere in WM (RTAB-Map since 2013).
  // "best_neighbours": the paper's 2011 code (Rtabmap::selectHypotheses): the highest of the
  // neighbour sums over every WM location, named by the highest posterior inside that sum.
  std::string hypothesis_value = "loop_mass";
  // LoopRatio of the paper's 2011 code: a hypothesis is accepted only when its value is at least
  // this times the previous image's highest hypothesis value (and that one was not 0), so that a
  // loop closure is accepted on a rising or steady hypothesis, not on the first image of one.
  // 0: off (the paper's text; memloop).
  double loop_ratio = 0;
  // Scores of L_t against WM (III-C): "similarity", eq. 1 (the paper), or "tfidf", the sum over
  // shared words of n_wj / n_j * log10(N / n_w) (RTAB-Map since 2013).
  std::string likelihood = "similarity";
  // 1: a hypothesis is accepted only when the image's own likelihood for it stands out (eq. 3
  // above 1), not on the prior alone (memloop); 0: the paper.
  int require_support = 1;
  // A hypothesis is accepted only when the image shares at least this many words (eq. 1's
  // N_pair) with L_i (memloop); 0: the paper. One or two shared words are chance collisions in a
  // dictionary of 10^4-10^5 words, yet eq. 3 makes them "stand out" when every score is as low.
  int min_shared_words = 3;
  // With require_support, when Rehearsal gave L_t an older image's words (III-B: "z_t is cleared
  // and z_c is copied into z_t"), the image's own words must support the loop closure too
  // (min_shared_words shared, eq. 1 score >= eq. 3's mu): a camera turning away keeps merging
  // into the older signature, and the filter would otherwise accept a place the older image saw
  // and the image no longer does. 2 (the default): they must support L_i or a WM location linked
  // to it, and the loop closure names the one they support best, L_i first (the filter's mass
  // spreads over L_i's neighbours; the merged words say which neighbourhood, the image's own
  // words where in it). 1: L_i only (on generated forward-moving routes it costs recall under WM
  // budgets). 0: z_t only, the paper (memloop; docs/design.md).
  int support_from_image = 2;
  // 1: when Rehearsal gave L_t an older image's words (III-B), the filter observes words it has
  // already observed, and a value that rises then rises on the same evidence counted again: the
  // value compared with T_loop is at most the previous image's. A merged image keeps a loop
  // closure the previous image accepted; it does not start one (memloop, in --preset hand-held).
  // 0: the paper and the default: on tum_fr1_rpy it moves a false positive from one WM budget
  // to another instead of removing it (docs/design.md).
  int cap_merged_images = 0;
  // 1: a hypothesis is not accepted while a location linked to it is in LTM (deferred for T_time,
  // or transferred) and looks more like the image than it does (memloop); 0: the paper.
  int ltm_neighbour_check = 1;
  // The whole-image channel's likelihood (features.whole_image): a WM location whose descriptor
  // scores z standard deviations above WM's mean gets exp(gain * (z - min_z)) when z > min_z,
  // else 1, multiplied into eq. 3; the virtual place gets the mean of those over WM, multiplied
  // into eq. 4. 0: the channel is kept but not weighed.
  double whole_image_gain = 2.5;
  double whole_image_min_z = 0.5;
  // With the channel, a hypothesis whose z there reaches this is supported by the image without
  // require_support's and min_shared_words' word evidence, which night images lack (0: never).
  double whole_image_support_z = 1.5;
  // With the channel, a loop closure is accepted only when the channel's best WM location (z at
  // least whole_image_support_z) lay within neighbour_range links of it in each of the last this
  // many images, not all one location (whole_image_agreement.h; 0: no check).
  int whole_image_agreement = 3;
  // Which WM locations the channel weighs: "earlier_sessions", those first seen in an earlier
  // session of the map (MapMode::kNewSession), or "all". Within one session the light is the
  // same and the words are the better judge: a whole image cannot tell look-alike places apart.
  std::string whole_image_scope = "earlier_sessions";
  // The channel stays out of an image whose words' eq. 3 value (before the channel's factor)
  // reaches this for a location in its scope: the words recognize the place, and a whole image,
  // which look-alike places share, would only pull the filter away (0: the channel weighs every
  // image).
  double whole_image_words_first = 3;
};

// Geometric verification of the highest hypothesis (epipolar_check.h): a loop closure is accepted
// only when the words L_t shares with L_i fit one fundamental matrix with enough inliers.
struct VerificationOptions {
  // Epipolar verification (epipolar_check.h). With `--preset verified` (Options::Verified()): a
  // hypothesis between T_verified and T_loop is a loop closure when the image's keypoints,
  // matched to L_i's by descriptor, fit one fundamental matrix that chance would not give and
  // the previous image agreed; over T_loop, appearance alone decides, as in the paper
  // (docs/design.md, "Verification under T_loop"). The paper has none: min_inliers 0.
  //
  // Inliers needed (0 = no verification, the paper).
  int min_inliers = 0;
  // The a-contrario number of false alarms the geometry may have (epipolar_significance.h): under
  // 1, fewer than one such fit is expected among random correspondences. 0 = not checked.
  double max_false_alarms = 0;
  // With loop_threshold: a hypothesis under T_loop is accepted only when the previous image's
  // hypothesis lay within FilterOptions::neighbour_range links of it and was 1 = over
  // T_verified, 2 = a loop closure or verified (0 = no check).
  int previous_agrees = 0;
  // T_verified: with min_inliers, a hypothesis whose value is over this but not over T_loop is a
  // loop closure when verification passes, and one over T_loop is without it. 0: every eligible
  // hypothesis is verified, and T_loop alone accepts.
  double loop_threshold = 0;
  // What the fundamental matrix is fitted to: "descriptors", the image's keypoints matched to
  // the location's by descriptor (descriptor_correspondences.h), or "words", the words both hold
  // once (fewer on a changed viewpoint).
  std::string correspondences = "words";
  // RANSAC: largest distance, in pixels, of a point to its epipolar line to count as an inlier.
  double ransac_pixels = 3.0;
  // RANSAC: confidence that an all-inlier sample was drawn.
  double ransac_confidence = 0.99;
  // A loop closure is refused when the camera's roll between its two views, measured from where
  // their shared words are (view_roll.h), is over this many degrees (0 = no check, the paper).
  double max_roll_degrees = 0;
};

// The camera's pinhole intrinsics, in pixels: with fx and fy set, each accepted loop closure
// comes with the geometry between its two views (Result::loop_closure_geometry: epipolar
// inliers, relative pose). 0 = unknown: nothing is computed.
struct CameraOptions {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

struct Options {
  FeatureOptions features;
  DictionaryOptions dictionary;
  MemoryOptions memory;
  FilterOptions filter;
  VerificationOptions verification;
  CameraOptions camera;

  // The paper's mechanisms as written (Labbe & Michaud 2011): rotation-invariant SURF, STM 25,
  // the neighbour-summed hypothesis, transfer by weight and age only; where the text is silent,
  // what the paper's 2011 code did (introlab/rtabmap 2d73090f: its SURF and ratio test, the
  // highest neighbour sum, LoopRatio, retrieved locations kept 10 iterations). docs/design.md
  // lists each choice, what the defaults change, and what each change measured.
  static Options Paper2011();
  // The defaults for a camera that rolls about its axis (hand-held, walking): U-SURF described in
  // each image's rolled frame, loop closures refused between views rolled apart, and a loop
  // closure needs the image's own words after a Rehearsal merge (docs/design.md, "Camera roll").
  static Options HandHeld();
  // The defaults with the whole-image channel, for places revisited under another light (day,
  // then night: docs/design.md, "Whole-image channel").
  static Options DayNight();
  // memloop's defaults with loop closures under T_loop that geometry confirms, for a camera that
  // moves (docs/design.md, "Verification under T_loop").
  static Options Verified();
};

// Names accepted by `--preset` and Preset(): "default", "paper2011", "hand-held", "day-night"
// and "verified".
Options Preset(const std::string& name);

}  // namespace memloop
