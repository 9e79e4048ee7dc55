#include "memloop/params.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "memloop/errors.h"
#include "util/excerpt.h"

namespace memloop {
namespace {

// Builds one row of the registry: Param(key, field).Unit(..).Range(..).Help(..).
class Param {
 public:
  Param(std::string key, Parameter::Accessor field) {
    row_.key = std::move(key), row_.field = field;
  }
  Param& Unit(std::string unit) { return row_.unit = std::move(unit), *this; }
  Param& Range(double min, double max) { return row_.min = min, row_.max = max, *this; }
  Param& AboveRange(double min, double max) {
    return Range(min, max), row_.min_exclusive = true, *this;
  }
  Param& Choices(std::vector<std::string> choices) {
    return row_.choices = std::move(choices), *this;
  }
  // An on/off switch (an int field holding 0 or 1): true/false, on/off, yes/no or 1/0.
  Param& Flag() { return Range(0, 1), row_.flag = true, *this; }
  Param& Symbol(std::string symbol) { return row_.symbol = std::move(symbol), *this; }
  Param& Help(std::string description) { return row_.description = std::move(description), *this; }
  operator Parameter() const { return row_; }

 private:
  Parameter row_;
};

#define MEMLOOP_FIELD(path)   \
  +[](Options & o) -> auto& { \
    return o.path;            \
  }

// clang-format off
std::vector<Parameter> MakeRegistry() {
  constexpr double kHuge = 1e9;
  return {
    Param("features.type", MEMLOOP_FIELD(features.type)).Choices({"surf", "sift", "orb"})
        .Help("Feature backend: surf (memloop's SURF, 64-d), sift (OpenCV SIFT, 128-d), orb (OpenCV ORB, 256-bit binary)"),
    Param("features.max_features", MEMLOOP_FIELD(features.max_features)).Unit("keypoints")
        .Range(0, 100000).Help("Strongest keypoints kept per image (0 = all)"),
    Param("features.min_image_side", MEMLOOP_FIELD(features.min_image_side)).Unit("pixels")
        .Range(0, 100000).Help("Images whose smaller side is under this are enlarged (bilinear, smallest integer factor that reaches it, lowered to keep at most 4 million pixels) before feature extraction; keypoints stay in the image's pixels (0 = never)"),
    Param("surf.hessian_threshold", MEMLOOP_FIELD(features.surf_hessian_threshold))
        .Range(0, kHuge).Help("SURF: minimum det(H) of a keypoint, on 0-255 intensities (as OpenCV)"),
    Param("surf.octaves", MEMLOOP_FIELD(features.surf_octaves)).Range(1, 8)
        .Help("SURF: octaves of filter sizes"),
    Param("surf.intervals", MEMLOOP_FIELD(features.surf_intervals)).Range(3, 8)
        .Help("SURF: filter sizes per octave (maxima are searched in the inner ones)"),
    Param("surf.sample_step", MEMLOOP_FIELD(features.surf_sample_step)).Unit("pixels").Range(1, 8)
        .Help("SURF: sampling step of the first octave, doubled per octave"),
    Param("surf.extended", MEMLOOP_FIELD(features.surf_extended)).Flag()
        .Help("SURF: true for 128-d descriptors, false for 64-d"),
    Param("sift.upright", MEMLOOP_FIELD(features.sift_upright)).Flag()
        .Help("SIFT: true describes every keypoint at angle 0 (upright, not rotation invariant); false = OpenCV's orientation"),
    Param("orb.upright", MEMLOOP_FIELD(features.orb_upright)).Flag()
        .Help("ORB: true describes every keypoint at angle 0 (upright, not rotation invariant); false = OpenCV's orientation"),
    Param("surf.upright", MEMLOOP_FIELD(features.surf_upright)).Flag()
        .Help("SURF: true for U-SURF (no orientation: faster, not rotation invariant)"),
    Param("surf.max_roll_degrees", MEMLOOP_FIELD(features.surf_max_roll_degrees)).Unit("degrees").Range(0, 45)
        .Help("U-SURF: an image whose edges show the camera rolled by at most this is described in the rolled frame (0 = at angle 0)"),
    Param("surf.min_roll_strength", MEMLOOP_FIELD(features.surf_min_roll_strength)).Range(0, 1)
        .Help("U-SURF with surf.max_roll_degrees or surf.rolled_view_degrees: the roll estimate's strength (edges on one axis pair, 0..1) needed to use it"),
    Param("surf.min_roll_degrees", MEMLOOP_FIELD(features.surf_min_roll_degrees)).Unit("degrees").Range(0, 45)
        .Help("U-SURF with surf.max_roll_degrees or surf.rolled_view_degrees: a smaller estimated roll is left at angle 0, as U-SURF (which tolerates it)"),
    Param("surf.rolled_view_degrees", MEMLOOP_FIELD(features.surf_rolled_view_degrees)).Unit("degrees").Range(0, 45)
        .Help("U-SURF: an image whose edges show the camera rolled by surf.min_roll_degrees to this is also matched in the rolled frame, a second view beside the upright one: each WM location scores the better of the two (0 = off)"),
    Param("features.whole_image", MEMLOOP_FIELD(features.whole_image)).Flag()
        .Help("true: each location also keeps a whole-image descriptor (HOG of a 128x64 thumbnail, 756 bytes) that the filter weighs beside the words (filter.whole_image_gain): loops across day and night"),
    Param("dictionary.nndr_ratio", MEMLOOP_FIELD(dictionary.nndr_ratio)).AboveRange(0, 1)
        .Help("Nearest-neighbour distance ratio (true L2): d1 < ratio*d2 joins a word, else a new word"),
    Param("dictionary.kd_trees", MEMLOOP_FIELD(dictionary.kd_trees)).Unit("trees").Range(1, 64)
        .Help("Randomized kd-trees in the dictionary's forest (FLANN)"),
    Param("dictionary.kd_checks", MEMLOOP_FIELD(dictionary.kd_checks)).Unit("leaves").Range(1, 100000)
        .Help("Leaves visited per nearest-neighbour search (FLANN checks)"),
    Param("dictionary.search_threads", MEMLOOP_FIELD(dictionary.search_threads)).Unit("threads").Range(1, 64)
        .Help("Threads sharing each search of the dictionary, the caller's included (the same words whatever the number)"),
    Param("dictionary.rebuild_fraction", MEMLOOP_FIELD(dictionary.rebuild_fraction)).AboveRange(0, 100)
        .Help("Rebuild the forest when points added+removed since the last build exceed this fraction of its size then"),
    Param("dictionary.rebuild_delay", MEMLOOP_FIELD(dictionary.rebuild_delay)).Unit("insertions").Range(0, 100000)
        .Help("A full rebuild runs in the background and replaces the forest this many insertions (~images) later; 0 = inside the iteration"),
    Param("dictionary.seed", MEMLOOP_FIELD(dictionary.seed)).Range(0, 2147483647)
        .Help("Seed of the forest's random splits (repeatable runs)"),
    Param("dictionary.lsh_tables", MEMLOOP_FIELD(dictionary.lsh_tables)).Range(1, 64)
        .Help("Binary descriptors (orb): hash tables of the LSH index"),
    Param("dictionary.lsh_key_bits", MEMLOOP_FIELD(dictionary.lsh_key_bits)).Unit("bits").Range(1, 32)
        .Help("Binary descriptors (orb): bits per LSH hash key"),
    Param("dictionary.lsh_probe_level", MEMLOOP_FIELD(dictionary.lsh_probe_level)).Range(0, 4)
        .Help("Binary descriptors (orb): neighbouring LSH buckets probed (multi-probe level)"),
    Param("memory.stm_size", MEMLOOP_FIELD(memory.stm_size)).Unit("locations").Range(1, 100000)
        .Symbol("STM size").Help("Newest locations kept out of loop closure detection"),
    Param("memory.rehearsal_threshold", MEMLOOP_FIELD(memory.rehearsal_threshold)).Range(0, 1)
        .Symbol("T_rehearsal (eq. 1)").Help("Similarity above which the compared STM location is merged"),
    Param("memory.rehearsal_most_similar", MEMLOOP_FIELD(memory.rehearsal_most_similar)).Flag()
        .Symbol("III-B").Help("true: L_t is compared with every STM location and merged with the most similar one above T_rehearsal (the paper's 2011 code); false: newest first, the first above it (the paper's text)"),
    Param("memory.time_limit_ms", MEMLOOP_FIELD(memory.time_limit_ms)).Unit("ms").Range(0, kHuge)
        .Symbol("T_time").Help("Iteration time above which WM locations go to LTM (0 = infinity)"),
    Param("memory.time_target", MEMLOOP_FIELD(memory.time_target)).Range(0.05, 1)
        .Help("Transfer when the iteration reaches this fraction of T_time (1 = the paper), so that whole iterations stay under T_time"),
    Param("memory.transfer_max_fraction", MEMLOOP_FIELD(memory.transfer_max_fraction)).Range(0, 1)
        .Help("Over the time target, transfer enough WM locations for the next iteration to fit, at most this fraction of WM per iteration (0 = the paper: words transferred = words added)"),
    Param("memory.wm_min_time_share", MEMLOOP_FIELD(memory.wm_min_time_share)).Range(0, 1)
        .Help("Over the time target, WM's stages (likelihood, filter, selection) keep what the other stages leave of the target and at least this share of it; only WM beyond is transferred for time (0 = the paper: every iteration over the target transfers)"),
    Param("memory.signature_within_time", MEMLOOP_FIELD(memory.signature_within_time)).Flag()
        .Help("true, with T_time on: an image's features are quantized strongest first until the iteration, with what its later steps are expected to take, would pass the time target; the weaker ones left are dropped (false = every feature whatever the time, the paper)"),
    Param("memory.signature_min_share", MEMLOOP_FIELD(memory.signature_min_share)).Range(0, 1)
        .Help("With memory.signature_within_time: of an image's features, at least this share (the strongest) is quantized however late the iteration"),
    Param("memory.signature_room_for_retrieval", MEMLOOP_FIELD(memory.signature_room_for_retrieval)).Flag()
        .Help("With memory.signature_within_time: after an iteration that deferred a retrieval for lack of time, the next image's features are quantized only while the deferred locations and the transfer after them still fit under T_time (fewer features, at least memory.signature_min_share), so that the place recognized comes back before the robot has moved on (false = the time target alone)"),
    Param("memory.signature_min_checks", MEMLOOP_FIELD(memory.signature_min_checks)).Unit("leaves")
        .Range(0, 100000).Help("With memory.signature_within_time: when an image's features would not all be quantized by the time target, their kd-forest search visits fewer leaves than dictionary.kd_checks (in proportion to the time left), down to this many, before any feature is dropped (0 = always dictionary.kd_checks)"),
    Param("memory.over_time_goal", MEMLOOP_FIELD(memory.over_time_goal)).Range(0, 0.5)
        .Help("With memory.signature_within_time: the share of iterations that may pass T_time; the quantization's deadline moves 10% of the time target earlier after each iteration over T_time and back by that x goal / (1 - goal) after each within, between half the time target and the target, so that iterations pass T_time at this rate when the machine varies more than the steps' estimates (0 = the time target alone)"),
    Param("memory.max_wm_locations", MEMLOOP_FIELD(memory.max_wm_locations)).Unit("locations")
        .Range(0, kHuge).Help("Deterministic budget: transfer while WM is larger (0 = none)"),
    Param("memory.max_dictionary_words", MEMLOOP_FIELD(memory.max_dictionary_words)).Unit("words")
        .Range(0, kHuge).Help("Deterministic budget: transfer while the dictionary is larger (0 = none); bounds memory (about 1.7 KB per word) and, with it, WM and the time per image; 100,000 is the size the paper reached under T_time"),
    Param("memory.max_retrieved", MEMLOOP_FIELD(memory.max_retrieved)).Unit("locations")
        .Range(0, 1000).Help("Locations retrieved from LTM per iteration, at most"),
    Param("memory.retrieved_immune_iterations", MEMLOOP_FIELD(memory.retrieved_immune_iterations)).Unit("iterations")
        .Range(1, 100000).Symbol("III-F").Help("A retrieved location is not transferred during this many iterations, the retrieving one included (1 = the paper's text; its 2011 code: 10)"),
    Param("memory.retrieved_kept_last_iterations", MEMLOOP_FIELD(memory.retrieved_kept_last_iterations)).Unit("iterations")
        .Range(0, 100000).Help("During this many iterations, the retrieving one included, a retrieved location leaves WM only after all the others, budgets still met (0 = off, the paper)"),
    Param("memory.retrieval_min_value", MEMLOOP_FIELD(memory.retrieval_min_value)).Range(0, 1)
        .Help("The highest hypothesis' LTM neighbours are retrieved only when its value (the one compared with T_loop) reaches this (0 = whatever the value, the paper)"),
    Param("memory.retrieval_strong_value", MEMLOOP_FIELD(memory.retrieval_strong_value)).Range(0, 1)
        .Help("Under T_time, a highest hypothesis under this value is retrieved for only when its retrieval is expected to end within the first half of T_time (0 = off, the paper)"),
    Param("memory.retrieval_within_time", MEMLOOP_FIELD(memory.retrieval_within_time)).Flag()
        .Help("true, with T_time on: a location is retrieved only when the iteration still ends under T_time with it, the others wait for a later one (false = up to memory.max_retrieved whatever the time, the paper)"),
    Param("memory.retrieval_read_ahead", MEMLOOP_FIELD(memory.retrieval_read_ahead)).Flag()
        .Help("true, with T_time on and memory.retrieval_within_time: a thread reads the map-file rows of the locations to retrieve and hands them over (the detector's thread does not read the file), and one is retrieved once they are read, waited for only as long as the iteration allows (false = read when retrieved, whatever the disk takes, the paper)"),
    Param("memory.retrieval_over_iterations", MEMLOOP_FIELD(memory.retrieval_over_iterations)).Flag()
        .Help("true, with the read-ahead: a location's words that left the dictionary are re-matched a chunk at a time while iterations have room, and it is retrieved once they all are (false = retrieved whole in one iteration, or deferred)"),
    Param("memory.retrieval_ahead_unsearched", MEMLOOP_FIELD(memory.retrieval_ahead_unsearched)).Flag()
        .Help("true, under T_time with memory.retrieval_over_iterations: neighbours that lie ahead of the place asked for (the way the robot goes along the old route) are asked for first, and their words the iteration has no room to search are not searched (no twins yet) but compared at retrieval with the words that joined since (false = every staged word searched, nearest then oldest first)"),
    Param("memory.retrieval_recent_twins", MEMLOOP_FIELD(memory.retrieval_recent_twins)).Unit("images")
        .Range(-1, 31).Help("Under T_time, with memory.retrieval_over_iterations: a location asked for whose words the iteration has no room to search comes back at once, its words compared only with the words that joined since the retrieval step this many images before (its twins, made by the images that recognize it), not searched in the kd-forest (-1 = it waits until its words are searched)"),
    Param("memory.retrieval_stage_deferred", MEMLOOP_FIELD(memory.retrieval_stage_deferred)).Flag()
        .Help("true, under T_time with memory.retrieval_over_iterations: a location asked for when no retrieval fits any more is staged all the same, so that the next extraction searches its words and the next iterations carry it on (false = asked for again only if a later image asks)"),
    Param("memory.retrieval_kd_checks", MEMLOOP_FIELD(memory.retrieval_kd_checks)).Unit("leaves")
        .Range(0, 100000).Help("Under T_time, with memory.retrieval_over_iterations: leaves the kd-forest search visits when re-matching a staged location's words that left the dictionary (0 = dictionary.kd_checks, as with T_time off)"),
    Param("memory.checkpoint_interval", MEMLOOP_FIELD(memory.checkpoint_interval)).Unit("images")
        .Range(1, 100000).Help("A resume checkpoint of STM, WM, dictionary and filter every this many images; a crash loses at most twice as many"),
    Param("memory.checkpoint_max_skipped", MEMLOOP_FIELD(memory.checkpoint_max_skipped)).Unit("images")
        .Range(0, 100000).Help("With T_time on, an image's checkpoint is skipped while the previous one is still being committed, at most this many in a row; a crash then loses up to as many images more (0 = always waited for)"),
    Param("memory.appearance_retrieval", MEMLOOP_FIELD(memory.appearance_retrieval)).Flag()
        .Help("true: the LTM location that looks most like the image is retrieved with its neighbours when it stands out (false = only the highest hypothesis' neighbours, the paper)"),
    Param("memory.fleet_imports", MEMLOOP_FIELD(memory.fleet_imports)).Unit("places")
        .Range(0, 100000).Help("A fleet's map (a server map with --robot): places other robots stored that join this robot's WM per image, as retrieved places do, read from the server in the background; under T_time only while the iteration is within half its target (0 = other robots' places are not searched)"),
    Param("memory.appearance_vocabulary", MEMLOOP_FIELD(memory.appearance_vocabulary)).Unit("words")
        .Range(16, 1000000).Help("Entries of the fixed vocabulary (the dictionary's first words) that describes locations for retrieval by appearance"),
    Param("memory.appearance_min_z", MEMLOOP_FIELD(memory.appearance_min_z)).Range(0, 1000)
        .Help("Standard deviations above LTM's mean score the best LTM location needs to be retrieved by appearance"),
    Param("memory.appearance_chance_multiple", MEMLOOP_FIELD(memory.appearance_chance_multiple)).Range(0, 100)
        .Help("The best LTM location also needs a z of this many times sqrt(2 ln N), how far the best of N chance scores stands out over N LTM locations, so that chance offers do not grow with LTM (0 = memory.appearance_min_z alone)"),
    Param("memory.appearance_max_postings", MEMLOOP_FIELD(memory.appearance_max_postings)).Unit("postings")
        .Range(0, kHuge).Help("Retrieval by appearance sums the image's rarest vocabulary entries first and stops before their LTM postings pass this many, so that its time does not grow with LTM (0 = every entry)"),
    Param("memory.protect_hypothesis", MEMLOOP_FIELD(memory.protect_hypothesis)).Flag()
        .Help("true: the highest hypothesis' neighbourhood leaves WM after every other location (false = by weight and age, the paper)"),
    Param("memory.localization", MEMLOOP_FIELD(memory.localization)).Flag()
        .Help("true: match images against an existing map without extending or modifying it (its file is opened read-only); false = mapping"),
    Param("filter.loop_threshold", MEMLOOP_FIELD(filter.loop_threshold)).Range(0, 1)
        .Symbol("T_loop").Help("Hypothesis value (filter.hypothesis_value) above which a loop closure is accepted"),
    Param("filter.min_hypotheses", MEMLOOP_FIELD(filter.min_hypotheses)).Unit("locations")
        .Range(0, 100000).Symbol("T_minHyp").Help("WM locations needed before a loop closure can be accepted"),
    Param("filter.virtual_place_stay", MEMLOOP_FIELD(filter.virtual_place_stay)).Range(0, 1)
        .Symbol("p(S_t=-1|S_t-1=-1)")
        .Help("Transition: new location after new location; 1 minus it goes to loop closures"),
    Param("filter.neighbour_range", MEMLOOP_FIELD(filter.neighbour_range)).Unit("links").Range(0, 100)
        .Help("Transition and hypothesis sum reach this many links from a location"),
    Param("filter.neighbour_sigma", MEMLOOP_FIELD(filter.neighbour_sigma)).Unit("links")
        .AboveRange(0, 100).Help("Standard deviation of the transition model's discretized Gaussian"),
    Param("filter.min_sigma_ratio", MEMLOOP_FIELD(filter.min_sigma_ratio)).Range(0, 10)
        .Symbol("eq. 3-4").Help("sigma is at least this fraction of mu, so mu/sigma+1 stays continuous and at most 1/ratio+1 (0 = as written: sigma=0 gives 2)"),
    Param("filter.no_signal_virtual_place", MEMLOOP_FIELD(filter.no_signal_virtual_place)).Range(0, 1000)
        .Symbol("eq. 4").Help("p(L_t|S_t=-1) when no score stands out (none >= mu+sigma, or sigma ~ 0), instead of mu/sigma+1 (the paper's 2011 code: 2; 0 = eq. 4 as written)"),
    Param("filter.hypothesis_value", MEMLOOP_FIELD(filter.hypothesis_value)).Choices({"neighbours", "best_neighbours", "loop_mass"})
        .Symbol("III-D").Help("Value compared with T_loop: neighbours (posterior summed around the highest hypothesis, the paper), best_neighbours (the highest neighbour sum over WM, named by its highest posterior: the paper's 2011 code) or loop_mass (1 - p(virtual place))"),
    Param("filter.loop_ratio", MEMLOOP_FIELD(filter.loop_ratio)).Range(0, 10)
        .Help("Accept a hypothesis only when its value is at least this times the previous image's highest hypothesis value, itself not 0 (the paper's 2011 code: 0.9; 0 = off)"),
    Param("filter.likelihood", MEMLOOP_FIELD(filter.likelihood)).Choices({"similarity", "tfidf"})
        .Symbol("eq. 1 / III-C").Help("Score of L_t against each WM location: similarity (eq. 1, the paper) or tfidf (shared words weighted by log(N/n_w))"),
    Param("filter.require_support", MEMLOOP_FIELD(filter.require_support)).Flag()
        .Symbol("eq. 3").Help("true: accept only a hypothesis whose own likelihood stands out this image (s >= mu + sigma), not one carried by the prior alone (false = the paper)"),
    Param("filter.min_shared_words", MEMLOOP_FIELD(filter.min_shared_words)).Unit("words").Range(0, 100000)
        .Symbol("eq. 1").Help("accept only a hypothesis L_i with which the image shares at least this many words (N_pair): one or two are chance collisions (0 = the paper)"),
    Param("filter.support_from_image", MEMLOOP_FIELD(filter.support_from_image)).Range(0, 2)
        .Symbol("III-B").Help("With filter.require_support, when Rehearsal gave the image's location an older image's words, the image's own words must support the loop closure too (filter.min_shared_words shared, eq. 1 score >= eq. 3's mu): 2 = L_i or a WM location linked to it, which the loop closure then names (the best supported, L_i first); 1 = L_i only; 0 = the merged words alone (the paper)"),
    Param("filter.cap_merged_images", MEMLOOP_FIELD(filter.cap_merged_images)).Flag()
        .Symbol("III-B, III-D").Help("true: when Rehearsal gave the image's location an older image's words, the filter sees an observation it has seen, and the value compared with T_loop is at most the previous image's: a merged image keeps a loop closure, it does not start one (in --preset hand-held; false = the paper and the default)"),
    Param("filter.ltm_neighbour_check", MEMLOOP_FIELD(filter.ltm_neighbour_check)).Flag()
        .Help("true: no loop closure on L_i while a location linked to it is in LTM (deferred for T_time, or transferred) and looks more like the image (retrieval by appearance's descriptions; without them, any): the filter, which could not weigh it, may lag behind the robot (false = the paper)"),
    Param("filter.whole_image_gain", MEMLOOP_FIELD(filter.whole_image_gain)).Range(0, 100)
        .Symbol("eq. 3-4").Help("With features.whole_image: a WM location whose descriptor scores z standard deviations above WM's mean has its likelihood multiplied by exp(gain*(z-min_z)) when z > min_z, the virtual place's by the mean of those (0 = not weighed)"),
    Param("filter.whole_image_min_z", MEMLOOP_FIELD(filter.whole_image_min_z)).Unit("std. dev.").Range(0, 100)
        .Help("With features.whole_image: the z under which a location's whole-image likelihood is 1"),
    Param("filter.whole_image_support_z", MEMLOOP_FIELD(filter.whole_image_support_z)).Unit("std. dev.").Range(0, 100)
        .Help("With features.whole_image: a hypothesis standing out of WM by this z in the channel is supported by the image without filter.require_support's and filter.min_shared_words' words, which night images lack (0 = never)"),
    Param("filter.whole_image_agreement", MEMLOOP_FIELD(filter.whole_image_agreement)).Unit("images").Range(0, 1000)
        .Help("With features.whole_image: accept a loop closure only when the channel's best WM location (z >= filter.whole_image_support_z) lay within filter.neighbour_range links of it in each of the last this many images, not all one location (0 = no check)"),
    Param("filter.whole_image_scope", MEMLOOP_FIELD(filter.whole_image_scope)).Choices({"earlier_sessions", "all"})
        .Help("With features.whole_image: the WM locations the channel weighs, those first seen in an earlier session of the map (run --new-session; within a session the light is the same, and the words judge) or all"),
    Param("filter.whole_image_words_first", MEMLOOP_FIELD(filter.whole_image_words_first)).Range(0, 1000)
        .Symbol("eq. 3").Help("With features.whole_image: the channel stays out of an image whose words give a location in its scope an eq. 3 value of at least this: the words recognize the place (0 = the channel weighs every image)"),
    Param("verify.min_inliers", MEMLOOP_FIELD(verification.min_inliers)).Unit("matches").Range(0, 100000)
        .Help("Epipolar verification: correspondences fitting one fundamental matrix needed to accept a loop closure (0 = off, the paper)"),
    Param("verify.loop_threshold", MEMLOOP_FIELD(verification.loop_threshold)).Range(0, 1)
        .Symbol("T_verified").Help("With verify.min_inliers: a hypothesis over this but not over T_loop is a loop closure when epipolar verification passes; one over T_loop is without verification (0 = every hypothesis is verified, T_loop alone accepts)"),
    Param("verify.max_false_alarms", MEMLOOP_FIELD(verification.max_false_alarms)).Range(0, 1e9)
        .Symbol("NFA").Help("With verify.min_inliers: the most false alarms the epipolar geometry may have, the expected number of fits as good among random correspondences in images of this size (Moisan & Stival 2004; 0 = not checked)"),
    Param("verify.previous_agrees", MEMLOOP_FIELD(verification.previous_agrees)).Range(0, 2)
        .Help("With verify.loop_threshold: a hypothesis under T_loop is accepted only when the previous image's lay within filter.neighbour_range links of it and was 1 = over T_verified, 2 = a loop closure or verified (geometry alone cannot tell a corridor's repeated doors apart; 0 = no check)"),
    Param("verify.correspondences", MEMLOOP_FIELD(verification.correspondences)).Choices({"descriptors", "words"})
        .Help("Epipolar verification's correspondences: the image's keypoints matched to the location's by descriptor (mutual nearest neighbours, ratio 0.8), or the words both hold once"),
    Param("verify.ransac_pixels", MEMLOOP_FIELD(verification.ransac_pixels)).Unit("pixels").AboveRange(0, 1000)
        .Help("Epipolar verification: RANSAC inlier distance to the epipolar line"),
    Param("verify.ransac_confidence", MEMLOOP_FIELD(verification.ransac_confidence)).AboveRange(0, 1)
        .Help("Epipolar verification: RANSAC confidence"),
    Param("verify.max_roll_degrees", MEMLOOP_FIELD(verification.max_roll_degrees)).Unit("degrees").Range(0, 180)
        .Help("refuse a loop closure whose two views are rolled apart by more than this, measured from where their shared words are (0 = no check, the paper)"),
    Param("camera.fx", MEMLOOP_FIELD(camera.fx)).Unit("pixels").Range(0, 1e6)
        .Help("Focal length along x: with camera.fy, each loop closure comes with its epipolar inliers and the relative pose of its two views (essential matrix; 0 = unknown, none computed)"),
    Param("camera.fy", MEMLOOP_FIELD(camera.fy)).Unit("pixels").Range(0, 1e6)
        .Help("Focal length along y (0 = unknown)"),
    Param("camera.cx", MEMLOOP_FIELD(camera.cx)).Unit("pixels").Range(0, 1e6)
        .Help("Principal point, x"),
    Param("camera.cy", MEMLOOP_FIELD(camera.cy)).Unit("pixels").Range(0, 1e6)
        .Help("Principal point, y"),
  };
}
// clang-format on

#undef MEMLOOP_FIELD

// The shortest text that reads back as the same double (1234567, not 1.23457e+06; 0.2).
std::string FormatDouble(double value) {
  char text[32];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(text, sizeof(text), "%.*g", precision, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

bool ParseFlag(std::string text, bool* value) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (text == "true" || text == "on" || text == "yes" || text == "1") return *value = true, true;
  if (text == "false" || text == "off" || text == "no" || text == "0") return *value = false, true;
  return false;
}

// Strict parse: the whole text must be the number.
bool ParseDouble(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*value);
}

}  // namespace

bool Parameter::DefinesMap() const {
  if (key == "memory.appearance_vocabulary") return true;  // the locations' descriptions
  for (const char* group : {"features.", "surf.", "sift.", "orb.", "dictionary."}) {
    if (key.rfind(group, 0) == 0) return true;
  }
  return false;
}

std::string Parameter::TypeName() const {
  switch (field.index()) {
    case 0:
      return flag ? "bool" : "int";
    case 1:
      return "double";
    default:
      return "string";
  }
}

std::string Parameter::Get(const Options& options) const {
  Options& mutable_options = const_cast<Options&>(options);  // accessors only read here
  return std::visit(
      [&](auto accessor) -> std::string {
        const auto& value = accessor(mutable_options);
        using T = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<T, std::string>) {
          return value;
        } else if constexpr (std::is_same_v<T, int>) {
          if (flag) return value != 0 ? "true" : "false";
          return std::to_string(value);
        } else {
          return FormatDouble(value);
        }
      },
      field);
}

std::string Parameter::RangeText() const {
  if (flag) return "true|false";
  if (!choices.empty()) {
    std::string text;
    for (const auto& choice : choices) text += (text.empty() ? "" : "|") + choice;
    return text;
  }
  return (min_exclusive ? "(" : "[") + FormatDouble(min) + ", " + FormatDouble(max) + "]";
}

std::string Parameter::Check(const Options& options) const {
  if (!choices.empty()) {
    const std::string value = Get(options);
    for (const auto& choice : choices) {
      if (value == choice) return "";
    }
    return "must be one of " + RangeText();
  }
  double number = 0;
  Options& mutable_options = const_cast<Options&>(options);  // accessors only read here
  std::visit(
      [&](auto accessor) {
        const auto& field_value = accessor(mutable_options);
        if constexpr (!std::is_same_v<std::decay_t<decltype(field_value)>, std::string>) {
          number = static_cast<double>(field_value);
        }
      },
      field);
  if (flag && number != 0 && number != 1) return "must be 0 or 1 (false or true)";
  const bool above_min = min_exclusive ? number > min : number >= min;
  if (!above_min || number > max) return "must be in " + RangeText();
  return "";
}

void Parameter::Set(Options& options, const std::string& value) const {
  const auto fail = [&](const std::string& why) {
    throw ParameterError(key, "Invalid parameter " + key + " = '" + Excerpt(value) + "': " + why);
  };
  std::visit(
      [&](auto accessor) {
        auto& target = accessor(options);
        using T = std::decay_t<decltype(target)>;
        if constexpr (std::is_same_v<T, std::string>) {
          target = value;
        } else if (bool on = false; flag) {
          if (!ParseFlag(value, &on)) fail("not true or false (also on/off, yes/no, 1/0)");
          target = on ? 1 : 0;
        } else {
          double number = 0;
          if (!ParseDouble(value, &number)) fail("not a number");
          if (std::is_same_v<T, int> && number != std::floor(number)) fail("not a whole number");
          if (std::is_same_v<T, int> && std::fabs(number) > 2147483647.0) fail("out of range");
          target = static_cast<T>(number);
        }
      },
      field);
  const std::string problem = Check(options);
  if (!problem.empty()) fail(problem);
}

const std::vector<Parameter>& Parameters() {
  static const std::vector<Parameter> registry = MakeRegistry();
  return registry;
}

const Parameter* FindParameter(const std::string& key) {
  for (const auto& parameter : Parameters()) {
    if (parameter.key == key) return &parameter;
  }
  return nullptr;
}

namespace {

// Levenshtein distance: single-character edits from `a` to `b`.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "; did you mean 'memory.time_limit_ms'?" for a name within 3 edits of one parameter's.
std::string Suggestion(const std::string& key) {
  if (key.size() > 64) return "";  // no name is that long; spare the quadratic distance
  const Parameter* nearest = nullptr;
  size_t best = 4;
  for (const Parameter& parameter : Parameters()) {
    const size_t distance = EditDistance(key, parameter.key);
    if (distance < best) {
      best = distance;
      nearest = &parameter;
    }
  }
  return nearest ? "; did you mean '" + nearest->key + "'?" : "";
}

}  // namespace

void SetParameter(Options& options, const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw ParameterError(assignment, "Malformed parameter '" + Excerpt(assignment) +
                                         "': expected NAME=VALUE (see 'memloop params')");
  }
  const std::string key = assignment.substr(0, equals);
  const Parameter* parameter = FindParameter(key);
  if (parameter == nullptr) {
    throw ParameterError(
        key, "Unknown parameter '" + Excerpt(key) + "' (see 'memloop params')" + Suggestion(key));
  }
  parameter->Set(options, assignment.substr(equals + 1));
}

void ValidateOptions(const Options& options) {
  for (const auto& parameter : Parameters()) {
    const std::string problem = parameter.Check(options);
    if (!problem.empty()) {
      throw ParameterError(parameter.key, "Invalid parameter " + parameter.key + " = " +
                                              parameter.Get(options) + ": " + problem);
    }
  }
  if ((options.camera.fx > 0) != (options.camera.fy > 0)) {
    throw ParameterError(options.camera.fx > 0 ? "camera.fy" : "camera.fx",
                         "camera.fx and camera.fy: give both focal lengths, or neither");
  }
}

std::string ParametersMarkdown() {
  const Options defaults;
  std::ostringstream out;
  out << "# Parameters\n\n"
         "Generated by `memloop params --markdown` from the parameter registry "
         "(src/detector/params.cc); "
         "a test keeps this file in step with it. Set any of them with `--set NAME=VALUE`. "
         "Defaults are memloop's best measured values (docs/real-data.md); `--preset paper2011` "
         "gives the paper's (Sec. IV; where its text is silent, its 2011 code's), and "
         "docs/design.md lists each departure; `--preset hand-held` is for a camera that rolls "
         "about its axis (docs/design.md, \"Camera roll\"), `--preset day-night` for places "
         "revisited under another light, in a later session of the map (docs/design.md, "
         "\"Whole-image channel\"), `--preset verified` for loop closures under T_loop that "
         "geometry confirms (docs/design.md, \"Verification under T_loop\"). Parameters "
         "marked "
         "*map* define what a word is and how words are found: a map keeps them, and "
         "`memloop run --resume` refuses other values.\n\n"
         "| name | default | type | unit | range | paper | description |\n"
         "| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Parameter& p : Parameters()) {
    out << "| `" << p.key << "`" << (p.DefinesMap() ? " *map*" : "") << " | " << p.Get(defaults)
        << " | " << p.TypeName() << " | " << p.unit << " | " << p.RangeText() << " | " << p.symbol
        << " | " << p.description << " |\n";
  }
  return out.str();
}

}  // namespace memloop
