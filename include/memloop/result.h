// What one call of Detector::Process reports: the loop-closure decision, the highest hypothesis
// (also when below T_loop, so that precision-recall curves can be drawn), per-stage times and the
// sizes of the memories.
#pragma once

#include <string>
#include <vector>

#include "memloop/loop_geometry.h"
#include "memloop/types.h"

namespace memloop {

// Wall time of each step of the per-image cycle (paper Fig. 1), in milliseconds.
struct StageTimes {
  // The stages whose cost grows with WM (likelihood, filter, selection): what the time controller
  // scales, and what the fixed cost of an iteration leaves out.
  double WmStagesMs() const { return likelihood_ms + filter_ms + selection_ms; }

  double signature_ms = 0;   // features + quantization into words
  double rehearsal_ms = 0;   // III-B
  double likelihood_ms = 0;  // eq. 3-4
  double filter_ms = 0;      // eq. 2 with the transition model
  double selection_ms = 0;   // III-D
  double retrieval_ms = 0;   // III-E
  double transfer_ms = 0;    // III-F
  double checkpoint_ms = 0;  // the resume checkpoint queued for the map file
  // Of the iteration, the time spent waiting for the map file's writer (its queue full, or the
  // previous checkpoint not committed), in whichever step it happened.
  double ltm_wait_ms = 0;
  // Of the iteration, the time spent reading the map file (a retrieved location's rows and the
  // descriptors of its words), in whichever step: a row the OS does not hold takes the disk's
  // time, which the read-ahead (memory.retrieval_read_ahead) is there to spare the iteration.
  double ltm_read_ms = 0;
  // CPU time of the detector's thread over the iteration: total_ms minus this is time it did
  // not run (waiting for the search's other thread, the disk or the writer, or descheduled by
  // the OS), which tells a slow step from a stalled one. On a virtual machine, time the host
  // stopped the virtual CPU may count as CPU time.
  double cpu_ms = 0;
  double total_ms = 0;  // the whole iteration
};

struct Result {
  // False until Process() has run (a default Result says so).
  bool processed = false;
  ImageIndex image_index = kNoImage;
  double timestamp = kNoTimestamp;  // ImageInfo::timestamp, seconds
  int session = 0;                  // the map's session the image joined (Detector::session())
  // Location now standing for the image (after Rehearsal it may hold older images too);
  // kNoLocation in localization (memory.localization), where the image joins no location.
  LocationId location_id = kNoLocation;
  // STM location merged into this one by Rehearsal, kNoLocation when none.
  LocationId rehearsal_merged_id = kNoLocation;
  int feature_count = 0;
  // Of those, the weakest that were not quantized for lack of time (memory.signature_within_time):
  // the signature holds the others.
  int features_skipped = 0;
  int word_count = 0;  // words of the signature

  // Highest neighbour-summed hypothesis (III-D), accepted or not. kNoLocation when WM is empty.
  LocationId hypothesis_id = kNoLocation;
  double hypothesis_value = 0;
  // Images of the highest hypothesis' location, so that a precision-recall curve can judge every
  // hypothesis against ground truth, accepted or not.
  std::vector<ImageIndex> hypothesis_images;
  // A fleet's map: the robot whose images those are when the location is another robot's place
  // (empty: this map's own).
  std::string hypothesis_robot;
  // True when T_loop alone decided the hypothesis: WM held T_minHyp locations and, with
  // verification on, it passed the epipolar check. A precision-recall curve sweeps T_loop over
  // eligible hypotheses only (others are refused at any threshold).
  bool hypothesis_eligible = false;
  // Epipolar inliers of the highest hypothesis; -1 when not checked (verification off, or WM
  // below T_minHyp).
  int hypothesis_inliers = -1;
  // The posterior of the virtual place, p(S_t = -1 | L^t).
  double virtual_place_probability = 1;

  // The accepted loop closure, kNoLocation when none.
  LocationId loop_closure_id = kNoLocation;
  // Images of the matched location, the matched image first: the one whose keypoints it holds
  // (Rehearsal may have given it an older image's), which loop_closure_geometry's pose is to.
  std::vector<ImageIndex> loop_closure_images;
  std::string loop_closure_robot;  // as hypothesis_robot
  // With camera.fx and camera.fy set: the geometry between the image and the matched location's
  // view (epipolar inliers, relative pose), as `memloop export` gives it; empty otherwise.
  LoopGeometry loop_closure_geometry;

  std::vector<LocationId> retrieved_ids;  // LTM -> WM this iteration
  // Retrievals left for a later iteration: with T_time on, no time was left for them.
  int retrievals_deferred = 0;
  // Of those, the ones whose rows the reader thread had not read from the map file in time
  // (memory.retrieval_read_ahead).
  int retrievals_unread = 0;
  // Retrieval by appearance (memory.appearance_retrieval): the LTM location that looks most like
  // the image and how far its score stands out of LTM's (standard deviations); kNoLocation when
  // none was searched or none shares anything with the image.
  LocationId appearance_match_id = kNoLocation;
  double appearance_match_z = 0;
  std::vector<LocationId> transferred_ids;  // WM -> LTM this iteration
  // A fleet's map: places of other robots that joined WM this iteration (memory.fleet_imports).
  std::vector<LocationId> fleet_imported_ids;

  int stm_size = 0;         // locations
  int wm_size = 0;          // locations
  int ltm_size = 0;         // locations
  int dictionary_size = 0;  // words
  StageTimes times;

  // What the time limit changed in this iteration, '|'-separated (empty: nothing; always empty
  // with T_time off): "transfer" (the iteration reached the time target and moved locations to
  // LTM), "features_skipped", "fewer_checks" (the features were searched visiting fewer leaves),
  // "retrieval_deferred" (a retrieval waited for time or for its rows), "retrieval_staged" (a
  // retrieval started earlier ended here), "rebuild_late" (the dictionary's forest, rebuilt in
  // the background, was not ready when due and not waited for). Only these depend on the
  // machine's speed: a run whose rows all have it empty repeats exactly; once one does not, the
  // rows after it may differ from another run's.
  std::string time_decided;
  void AddTimeDecision(const std::string& what);

  // What the map's server said since the previous image, one line each (a map on a server only):
  // its connection broke, and the robot goes on, its writes queued; it came back, and they were
  // committed.
  std::vector<std::string> map_notices;

  bool HasLoopClosure() const { return loop_closure_id != kNoLocation; }
  // One line: "image 41 -> location 38: loop closure with location 3 (image 2), p=0.62" (with
  // "robot b image 2" for another robot's place); in
  // localization "image 41: localized at location 3 (image 2), p=0.62".
  std::string Brief() const;
};

}  // namespace memloop
