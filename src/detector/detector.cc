#include "memloop/detector.h"

#include <optional>
#include <set>

#include "detector/appearance_retrieval.h"
#include "detector/bayes_filter.h"
#include "detector/checkpoint.h"
#include "detector/consistency.h"
#include "detector/detector_setup.h"
#include "detector/fleet_places.h"
#include "detector/hypothesis.h"
#include "detector/image_view.h"
#include "detector/likelihood.h"
#include "detector/loop_acceptance.h"
#include "detector/loop_geometry.h"
#include "detector/map_editor.h"
#include "detector/map_parameters.h"
#include "detector/memory.h"
#include "detector/neighbourhood_cache.h"
#include "detector/rehearsal.h"
#include "detector/retrieval_step.h"
#include "detector/rolled_view.h"
#include "detector/session_numbering.h"
#include "detector/signature_budget.h"
#include "detector/stopwatch.h"
#include "detector/transfer.h"
#include "detector/whole_image_likelihood.h"
#include "features/whole_image_descriptor.h"
#include "memloop/errors.h"
#include "memloop/feature_extractor.h"
#include "memloop/params.h"
#include "storage/long_term_memory.h"
#include "vocabulary/appearance_index.h"

namespace memloop {
class Detector::Impl {
 public:
  Impl(const Options& options, const std::string& database_path, MapMode mode)
      : options_(Validated(options)),
        localizing_(options_.memory.localization != 0),
        selection_options_(SelectionOptions(options_)),
        extractor_(FeatureExtractor::Create(options.features)),
        memory_(extractor_->Kind(), extractor_->DescriptorDim(), DictionaryOptionsOf(options_)),
        filter_(options.filter),
        ltm_(database_path, FileMode(mode)),
        retrieval_(options_.memory, options_.filter.neighbour_range, memory_, ltm_),
        appearance_(MakeAppearanceIndex(options_, *extractor_)),
        editor_(memory_, ltm_, filter_, appearance_.get()) {
    // A map a run left before its first checkpoint holds nothing to go on from: it starts afresh.
    const bool extends = localizing_ || (mode != MapMode::kNew && !HoldsNoImage(database_path));
    if (extends) Resume(database_path);  // nothing written before
    if (extends && mode == MapMode::kNewSession && !localizing_) StartSession();
    FollowFleet(database_path);
    WaitForDueRebuildsWithinTime();
    if (localizing_) {
      MoveStmToWm();
      return;
    }
    for (const Parameter& parameter : Parameters()) {
      ltm_.WriteInfo("param." + parameter.key, parameter.Get(options_));
    }
  }

  // With T_time on, a forest rebuild that is due but not done is waited for while the iteration
  // has time to spare: half of what is left before time_target x T_time. The same images then
  // use the same forest as with T_time off, unless time is short (issue 35).
  void WaitForDueRebuildsWithinTime() {
    const double target_ms = options_.memory.time_target * options_.memory.time_limit_ms;
    if (target_ms <= 0) return;
    memory_.dictionary().SetSwapWait(
        [this, target_ms] { return 0.5 * (target_ms - iteration_.ElapsedMs()); });
  }

  // The paper's Fig. 1, one call per box.
  Result Process(const cv::Mat& image, const cv::Mat& depth, const ImageInfo& info) {
    if (closed_) throw Error("Detector::Process called after Close()");
    if (failed_) throw Error("Detector::Process called after a failed iteration");
    ltm_.CheckWriter();                  // a map that no longer follows memory stops the run here
    const cv::Mat gray = ToGray(image);  // bad input is refused before anything changes
    depth_ = DepthInMetres(depth, image.size());
    sessions_.CheckImage(info.index);
    try {
      return localizing_ ? Localize(gray, info) : Iterate(gray, info);
    } catch (...) {
      failed_ = true;  // memory is half-updated: the file stays at its last checkpoint
      throw;
    }
  }

  void Flush() {
    if (!failed_ && !closed_ && !localizing_) WriteCheckpoint();
    ltm_.Flush();
  }
  size_t CatchUpWithFleet(double seconds) {
    if (closed_ || failed_) throw Error("Detector::CatchUpWithFleet called after Close()");
    return fleet_.CatchUp(seconds, counters_.last_image, memory_, ltm_, filter_, appearance_.get());
  }
  ImageIndex last_image() const { return counters_.last_image; }
  long long images_processed() const { return counters_.images_processed; }
  int session() const { return sessions_.id(); }
  ImageIndex session_first_image() const { return sessions_.first_image(counters_.last_image + 1); }
  void SetWriterHeld(bool held) { ltm_.SetWriterHeld(held); }
  std::vector<std::string> CheckConsistency(LtmCheck ltm_check = LtmCheck::kEvery) {
    std::vector<std::string> problems =
        memloop::CheckConsistency(memory_, ltm_, filter_, editor_.past_matches(), appearance_.get(),
                                  options_.features.whole_image != 0, 20, ltm_check);
    const int range = options_.filter.neighbour_range;
    if (wm_neighbourhoods_.Update(memory_, range) != memory_.WmNeighbourhoods(range)) {
      problems.push_back("the filter's kept neighbourhoods differ from a search of the graph");
    }
    return problems;
  }

  // Stores STM and WM locations (and their words) in LTM so that the file holds the whole map,
  // and a checkpoint so that it can be resumed. Written directly, not queued: no copy of WM's
  // words is held beside the dictionary while they are written.
  void Close() {
    if (closed_) return;
    closed_ = true;
    if (failed_ || localizing_) return;
    ltm_.WriteDirectly();
    std::set<WordId> words;
    for (const auto& [id, location] : memory_.locations()) {
      ltm_.Store(location);
      words.insert(location.signature.words.begin(), location.signature.words.end());
    }
    for (WordId word : words) ltm_.StoreWord(word, memory_.dictionary().Descriptor(word));
    WriteCheckpoint();
    ltm_.Flush();
  }

  // The LTM writer commits what is queued up to the last checkpoint when it stops, and drops
  // what follows it.
  void CloseAtLastCheckpoint() { closed_ = true; }

  const Options& options() const { return options_; }

 private:
  // The paper's Fig. 1, one call per box. The resume checkpoint of this image's state is written
  // at the start of the next one (StartIteration): see Detector::Process.
  Result Iterate(const cv::Mat& gray, const ImageInfo& info) {
    Result result = StartIteration(info);
    ltm_.RecordImage({result.image_index, sessions_.id(), info.name, info.timestamp});
    const Stopwatch& iteration = iteration_;
    const LocationId t = CreateLocation(gray, result);      // III-A
    Rehearse(t, result);                                    // III-B, eq. 1
    memory_.MoveStmOverflowToWm(options_.memory.stm_size);  // STM -> WM
    const Signature& z_t = memory_.at(t).signature;
    const Likelihood likelihood = ComputeObservation(z_t, result);            // eq. 3, 4
    const Neighbourhoods& neighbourhoods = UpdateFilter(likelihood, result);  // eq. 2
    const Hypothesis hypothesis =
        SelectLoopClosure(z_t, DescriptionOf(t), likelihood, neighbourhoods, result);  // III-D
    CloseLoop(t, hypothesis, neighbourhoods, result);                                  // III-D
    RetrieveFromLtm(iteration, hypothesis, DescriptionOf(t), result);                  // III-E
    TransferToLtm(iteration, hypothesis, result);                                      // III-F
    ImportFleetPlaces(iteration, result);  // a fleet's map: other robots' places join WM
    checkpoint_due_ = counters_.images_processed % options_.memory.checkpoint_interval == 0;
    Summarize(t, z_t, iteration, result);
    return result;
  }

  // Localization (memory.localization): Fig. 1 without the boxes that change the map. The image
  // is matched against WM but does not join the map: no location, word, link or weight is made,
  // nothing is written. Retrieval and transfer still move locations between WM and LTM (III-E,
  // F), in memory only: LTM is read-only and keeps what leaves WM in its overlay.
  Result Localize(const cv::Mat& gray, const ImageInfo& info) {
    Result result = StartIteration(info);
    const Stopwatch& iteration = iteration_;
    Appearance appearance;
    const Signature z_t = MatchImage(gray, result, &appearance);              // III-A
    const Likelihood likelihood = ComputeObservation(z_t, result);            // eq. 3, 4
    const Neighbourhoods& neighbourhoods = UpdateFilter(likelihood, result);  // eq. 2
    const Hypothesis hypothesis =
        SelectLoopClosure(z_t, &appearance, likelihood, neighbourhoods, result);  // III-D
    RetrieveFromLtm(iteration, hypothesis, &appearance, result);                  // III-E
    TransferToLtm(iteration, hypothesis, result);                                 // III-F
    Summarize(kNoLocation, z_t, iteration, result);
    return result;
  }

  Result StartIteration(const ImageInfo& info) {
    iteration_ = Stopwatch();
    late_steps_at_start_ = memory_.dictionary().late_steps();
    // Waits and reads between images are not this iteration's; the checkpoint's below are (its
    // wait for the writer is ltm_wait_ms, its CPU in cpu_ms, as its time is in iteration_ms).
    ltm_.TakeWriterWaitMs();
    ltm_.TakeFileReadMs();
    iteration_cpu_start_ms_ = ThreadCpuMs();
    Result result;
    WriteDueCheckpoint(result);  // the previous image's, before anything changes
    result.processed = true;
    result.image_index = info.index == kNoImage ? counters_.last_image + 1 : info.index;
    result.timestamp = info.timestamp;
    result.session = sessions_.id();
    sessions_.Record(result.image_index);
    ++counters_.images_processed;
    counters_.last_image = result.image_index;
    dictionary_size_at_start_ = memory_.dictionary().size();
    retrieved_immune_.StartIteration(counters_.images_processed);
    retrieved_kept_last_.StartIteration(counters_.images_processed);
    image_words_.reset();  // set by Rehearse, which localization does not call
    return result;
  }

  LtmDatabase::Mode FileMode(MapMode mode) const {
    if (localizing_) return LtmDatabase::Mode::kRead;  // whatever `mode`: the map must exist
    return mode == MapMode::kNew ? LtmDatabase::Mode::kCreate : LtmDatabase::Mode::kOpen;
  }

  // Localization: the map's STM is its newest places, as much part of it as WM's; with no new
  // image to keep out of detection, they join WM (in memory only).
  void MoveStmToWm() {
    const std::deque<LocationId> stm = memory_.stm();
    memory_.MoveStmOverflowToWm(0);
    for (LocationId id : stm) filter_.Add(id);
  }

  // MapMode::kNewSession: nothing links the new session's first location to the old ones, the
  // filter forgets where the robot was, and STM joins WM (a new image is not the continuation of
  // the last session's, so nothing holds them out of the filter).
  void StartSession() {
    MoveStmToWm();
    filter_.Forget();
    counters_.newest_location = kNoLocation;
    counters_.previous_hypothesis_value = 0;
    sessions_.StartNew(counters_.last_image);
  }

  // A map a run killed before its first checkpoint left (ltm_ holds it open to write).
  bool HoldsNoImage(const std::string& path) {
    LtmDatabase database(path, LtmDatabase::Mode::kAttach);
    return MapHoldsNoImage(database);
  }

  // Restores memory, dictionary, filter and counters from the file's last checkpoint, after
  // checking that the map was made with the same map-defining parameters.
  void Resume(const std::string& path) {
    // ltm_ checked the file
    LtmDatabase database(path, localizing_ ? LtmDatabase::Mode::kRead : LtmDatabase::Mode::kAttach);
    CheckMapParameters(database, options_);
    const std::string use = localizing_ ? "localize against it" : "resume";
    counters_ = RestoreCheckpoint(database, memory_, filter_, editor_, retrieved_kept_last_, use);
    fleet_.Reload(database);
    for (const auto& [id, location] : memory_.locations()) ltm_.Exclude(id);
    if (appearance_) ReloadAppearance(database, memory_, ltm_, *appearance_);
    sessions_.Resume(database.ReadSessions(), counters_.last_image);
    // LTM near memory only: reading all of it had not finished after 15 minutes at 1,040,000
    // locations (bench/pad_map.py); the file's structure is SQLite's quick_check's, on opening.
    const std::vector<std::string> problems = CheckConsistency(LtmCheck::kNearMemory);
    if (!problems.empty()) {
      throw DatabaseError(
          path, "cannot " + use + ": the map is inconsistent (" + problems.front() +
                    (problems.size() > 1
                         ? ", and " + std::to_string(problems.size() - 1) + " more problems)"
                         : ")"));
    }
  }

  // The previous image's checkpoint, when memory.checkpoint_interval makes one due. With T_time
  // on, one the writer has not committed yet (SQLite folding its WAL into the file and flushing
  // the disk stalled up to 580 ms) is not waited for: this one is skipped, at most
  // memory.checkpoint_max_skipped in a row, and the next one holds its changes too (issue 9). A
  // crash then loses up to that many images more; with T_time off nothing is skipped.
  void WriteDueCheckpoint(Result& result) {
    if (!checkpoint_due_) return;
    checkpoint_due_ = false;
    if (options_.memory.time_limit_ms > 0 &&
        skipped_checkpoints_ < options_.memory.checkpoint_max_skipped &&
        ltm_.CheckpointInFlight()) {
      ++skipped_checkpoints_;
      return;
    }
    ScopedTimer timer(&result.times.checkpoint_ms);
    WriteCheckpoint();
  }

  void WriteCheckpoint() {
    checkpoint_due_ = false;
    skipped_checkpoints_ = 0;
    ltm_.Checkpoint(checkpoints_.Next(memory_, filter_, editor_.past_matches(), counters_,
                                      retrieved_kept_last_));
    memory_.ClearChanged();
  }

  // Localization's III-A: the image's features as words of the dictionary, none created.
  // With retrieval by appearance, `appearance` receives the image's description.
  Signature MatchImage(const cv::Mat& gray, Result& result, Appearance* appearance) {
    ScopedTimer timer(&result.times.signature_ms);
    Features features = ExtractFeatures(gray);
    result.feature_count = static_cast<int>(features.keypoints.size());
    Signature signature =
        signature_budget_.Match(features, memory_.dictionary(), &result.features_skipped);
    if (appearance_) {
      *appearance = appearance_->Describe(std::vector<WordId>(features.keypoints.size(), kNoWord),
                                          features.descriptors);
    }
    signature.whole_image = WholeImageOf(gray);
    rolled_view_.Observe(features, memory_.dictionary());
    KeepImageView(std::move(features), gray.size());
    return signature;
  }

  // The image's own keypoints: a loop closure's pose (camera.fx..cy), verification by descriptor.
  void KeepImageView(Features features, const cv::Size& size) {
    if (options_.camera.fx > 0 || VerifiesByDescriptors(options_.verification))
      image_view_ = ImageView(std::move(features), depth_, IntrinsicsOf(options_.camera));
    image_view_.image_size = size;
  }

  std::vector<uint8_t> WholeImageOf(const cv::Mat& gray) const {
    return options_.features.whole_image ? DescribeWholeImage(gray) : std::vector<uint8_t>{};
  }

  LocationId CreateLocation(const cv::Mat& gray, Result& result) {
    ScopedTimer timer(&result.times.signature_ms);
    Features features = ExtractFeatures(gray);
    result.feature_count = static_cast<int>(features.keypoints.size());
    int new_words = 0;
    const WordId first_new_word = memory_.dictionary().next_word_id();
    Signature signature = signature_budget_.Create(features, memory_.dictionary(), &new_words,
                                                   &result.features_skipped);
    rolled_view_.Observe(features, memory_.dictionary());  // after the words it may match
    signature.image = result.image_index;
    signature.whole_image = WholeImageOf(gray);
    Appearance appearance = Describe(signature, features.descriptors, first_new_word);
    KeepImageView(std::move(features), gray.size());
    const Location& location =
        memory_.AddToStm(std::move(signature), result.image_index, counters_.newest_location);
    counters_.newest_location = location.id;
    if (appearance_) {
      ltm_.StoreAppearance(location.id, appearance);
      appearance_->Add(location.id, std::move(appearance));
    }
    return location.id;
  }

  // III-A's features. Meanwhile, staged retrievals' words are searched on another thread
  // (retrieval_staging.h): the extraction does not touch the dictionary.
  Features ExtractFeatures(const cv::Mat& gray) {
    const auto searching = retrieval_.SearchBesideExtraction();
    return extractor_->Extract(gray);
  }

  Appearance Describe(const Signature& signature, const cv::Mat& descriptors,
                      WordId first_new_word) {
    if (!appearance_) return {};
    return DescribeNewLocation(*appearance_, ltm_, signature, descriptors, first_new_word);
  }

  const Appearance* DescriptionOf(LocationId id) const {
    return appearance_ ? appearance_->Find(id) : nullptr;
  }

  void Rehearse(LocationId t, Result& result) {
    ScopedTimer timer(&result.times.rehearsal_ms);
    RehearsalOutcome outcome =
        memloop::Rehearse(t, options_.memory.rehearsal_threshold, memory_, editor_,
                          options_.memory.rehearsal_most_similar != 0);
    result.rehearsal_merged_id = outcome.merged_id;
    if (outcome.merged_id != kNoLocation && options_.filter.support_from_image) {
      image_words_.emplace().words = std::move(outcome.replaced_words);
    }
  }

  Likelihood ComputeObservation(const Signature& z_t, Result& result) {
    ScopedTimer timer(&result.times.likelihood_ms);
    const bool tfidf = options_.filter.likelihood == "tfidf";
    IdMap<double> scores =
        tfidf ? ScoreWorkingMemoryTfIdf(z_t, memory_) : ScoreWorkingMemory(z_t, memory_);
    if (!tfidf) rolled_view_.Raise(memory_, z_t.size(), scores);  // eq. 1's, a rolled image's
    Likelihood likelihood = ComputeLikelihood(scores, options_.filter.min_sigma_ratio,
                                              options_.filter.no_signal_virtual_place);
    if (options_.features.whole_image) {  // the second channel (whole_image_likelihood.h)
      WeighWholeImage(z_t.whole_image, memory_, options_.filter, WholeImageBefore(), likelihood);
    }
    acceptance_.Observe(likelihood);
    return likelihood;
  }

  // filter.whole_image_scope: the channel weighs the locations first seen before this session's
  // first image, or all; localizing, the whole map is earlier than the images.
  ImageIndex WholeImageBefore() const {
    if (options_.filter.whole_image_scope == "all" || localizing_) return kNoImage;
    return session_first_image();
  }

  // The neighbourhoods stay valid until the next image's UpdateFilter.
  const Neighbourhoods& UpdateFilter(const Likelihood& likelihood, Result& result) {
    ScopedTimer timer(&result.times.filter_ms);
    const Neighbourhoods& neighbourhoods =
        wm_neighbourhoods_.Update(memory_, options_.filter.neighbour_range);
    filter_.Update(likelihood, neighbourhoods);
    return neighbourhoods;
  }

  Hypothesis SelectLoopClosure(const Signature& z_t, const Appearance* appearance,
                               const Likelihood& likelihood, const Neighbourhoods& neighbourhoods,
                               Result& result) {
    ScopedTimer timer(&result.times.selection_ms);
    Hypothesis hypothesis = SelectHypothesis(filter_.posterior(), filter_.virtual_place(),
                                             neighbourhoods, selection_options_);
    hypothesis.filter_id = hypothesis.id;
    const Signature& view = rolled_view_.ViewOf(hypothesis.id, z_t);  // what matched L_i
    acceptance_.Check(
        {z_t, view, result.rehearsal_merged_id != kNoLocation,
         image_words_ ? &*image_words_ : nullptr, likelihood, appearance, image_view_},
        counters_.previous_hypothesis_value, hypothesis, &result.hypothesis_inliers);
    result.hypothesis_id = hypothesis.id;
    result.hypothesis_eligible = hypothesis.eligible;
    result.hypothesis_value = hypothesis.value;
    if (hypothesis.id != kNoLocation) {
      result.hypothesis_images = ImagesOf(hypothesis.id, &result.hypothesis_robot);
    }
    result.virtual_place_probability = filter_.virtual_place();
    if (hypothesis.accepted) {
      result.loop_closure_id = hypothesis.id;
      result.loop_closure_images = result.hypothesis_images;
      result.loop_closure_robot = result.hypothesis_robot;
    }
    return hypothesis;
  }

  // III-D in the map: past matches out of the highest hypothesis' neighbourhood are absorbed,
  // and an accepted L_i links to L_t.
  void CloseLoop(LocationId t, const Hypothesis& hypothesis, const Neighbourhoods& neighbourhoods,
                 Result& result) {
    ScopedTimer timer(&result.times.selection_ms);
    AbsorbPastMatches(hypothesis, neighbourhoods);
    if (hypothesis.accepted) AcceptLoopClosure(t, hypothesis, result);
  }

  // III-D: L_t takes L_i's weight plus one and its neighbour links. L_i stays (its hypothesis
  // keeps the filter consistent) until it leaves the highest hypothesis' neighbourhood.
  void AcceptLoopClosure(LocationId t, const Hypothesis& hypothesis, Result& result) {
    const LocationId i = hypothesis.id;
    memory_.at(t).weight += memory_.at(i).weight + 1;
    const ForeignPlace* foreign = fleet_.Find(i);
    editor_.LinkLoopClosure(t, i, /*absorbed=*/foreign == nullptr);        // another robot's stays
    result.loop_closure_images = ImagesOf(i, &result.loop_closure_robot);  // with absorbed ones
    // camera.fx..cy: the pose for a SLAM back-end, from this image's and L_i's keypoints.
    result.loop_closure_geometry =
        DescribeLoopClosure(image_view_, result.image_index, memory_.at(i), memory_.dictionary(),
                            IntrinsicsOf(options_.camera), options_.verification);
    // The matched image is the one whose keypoints L_i holds, the view the pose is to: first.
    std::vector<ImageIndex>& images = result.loop_closure_images;
    const auto view =
        std::find(images.begin(), images.end(), result.loop_closure_geometry.match_view);
    if (view != images.end()) std::rotate(images.begin(), view, view + 1);
    ltm_.RecordLoopClosure({result.image_index, images.empty() ? kNoImage : images.front(), t, i,
                            hypothesis.value,
                            KeptPose(result.loop_closure_geometry, options_.camera.fx > 0),
                            /*added_by_edit=*/0, result.loop_closure_robot});
  }

  // The images location `id` stands for; of another robot (`robot` receives its name) when it is
  // that robot's place.
  std::vector<ImageIndex> ImagesOf(LocationId id, std::string* robot) const {
    const ForeignPlace* foreign = fleet_.Find(id);
    *robot = foreign ? foreign->robot : "";
    return foreign ? foreign->images : memory_.at(id).images;
  }

  // A fleet's map: places other robots stored since, at most memory.fleet_imports an image,
  // join WM as retrieved places do (fleet_places.h).
  void FollowFleet(const std::string& path) {
    if (IsServerMap(path) && !localizing_ && options_.memory.fleet_imports > 0) {
      fleet_.Follow(path, memory_.dictionary().descriptor_cv_type(), extractor_->DescriptorDim());
    }
  }
  // Under T_time, only while the iteration is within half of its time target.
  void ImportFleetPlaces(const Stopwatch& iteration, Result& result) {
    ScopedTimer timer(&result.times.retrieval_ms);
    const double target_ms = options_.memory.time_target * options_.memory.time_limit_ms;
    if (!fleet_.following() || (target_ms > 0 && iteration.ElapsedMs() > 0.5 * target_ms)) return;
    result.fleet_imported_ids =
        fleet_.Import(static_cast<size_t>(options_.memory.fleet_imports), result.image_index,
                      memory_, ltm_, filter_, appearance_.get());
  }

  // Past matches L_i out of the highest hypothesis' neighbourhood are deleted into the location
  // that matched them.
  void AbsorbPastMatches(const Hypothesis& hypothesis, const Neighbourhoods& neighbourhoods) {
    std::set<LocationId> near_highest;
    if (hypothesis.filter_id != kNoLocation) {
      for (const auto& entry : neighbourhoods.at(hypothesis.filter_id)) {
        near_highest.insert(entry.first);
      }
    }
    editor_.AbsorbPastMatches(near_highest);
  }

  // III-E: the highest hypothesis' LTM neighbours, when its value reaches
  // memory.retrieval_min_value (below, it is noise; under T_time, WorthRetrieving); then, with
  // retrieval by appearance, the LTM location that looks most like the image (`appearance`) and
  // its neighbours, when it stands out. With T_time on, each only if it still fits
  // (memory.retrieval_within_time).
  void RetrieveFromLtm(const Stopwatch& iteration, const Hypothesis& hypothesis,
                       const Appearance* appearance, Result& result) {
    signature_budget_.QuantizationOver();
    ScopedTimer timer(&result.times.retrieval_ms);
    const bool above_noise = WorthRetrieving(
        options_.memory, hypothesis.value, iteration.ElapsedMs(), retrieval_.ExpectedLocationMs());
    // Room is left for the transfer after it, most of whose work the paper's rule makes whatever
    // the time (words transferred = words added).
    const double transfer_ms = transfer_step_cost_.expected_ms();
    const std::vector<LocationId> retrieved = retrieval_.Retrieve(
        above_noise ? hypothesis.filter_id : kNoLocation, MatchByAppearance(appearance, result),
        [&](StepCost* cost) { return DeadlineOf(iteration, cost, transfer_ms); }, result);
    for (LocationId id : retrieved) {
      filter_.Add(id);  // a new state, probability 0
      if (appearance_) appearance_->Leave(id);
    }
    result.retrieved_ids = retrieved;
    // Room in the next image for what waited (memory.signature_room_for_retrieval): a place
    // recognized now is still there then, not two images on.
    const int waiting = std::min(result.retrievals_deferred, options_.memory.max_retrieved);
    signature_budget_.LeaveRoom(
        waiting > 0 ? waiting * retrieval_.ExpectedLocationMs() + transfer_ms : 0);
    retrieved_immune_.Retrieved(retrieved, counters_.images_processed);
    retrieved_kept_last_.Retrieved(retrieved, counters_.images_processed);
  }

  // Retrieval by appearance: the LTM location that looks most like the image, when it stands out
  // (memory.appearance_min_z, raised with LTM's size: AppearanceMinZ); kNoLocation otherwise.
  LocationId MatchByAppearance(const Appearance* appearance, Result& result) const {
    if (!appearance_ || appearance == nullptr) return kNoLocation;
    const AppearanceMatch match = appearance_->Best(*appearance);
    result.appearance_match_id = match.id;
    result.appearance_match_z = match.z;
    const double min_z = AppearanceMinZ(options_.memory, appearance_->searched_size());
    return match.z >= min_z ? match.id : kNoLocation;
  }

  // T_time on: a retrieval or a transfer must end under T_time. Off: no deadline. (Ending
  // retrievals by the time target instead halved them and left as many iterations over T_time:
  // 3.2% vs 2.9%, 6,000 images at 50 ms.)
  // `reserve_ms`: kept for the steps after it.
  StepDeadline DeadlineOf(const Stopwatch& iteration, StepCost* cost, double reserve_ms = 0) const {
    const double limit = options_.memory.time_limit_ms;
    if (limit <= 0) return StepDeadline();
    return StepDeadline([&iteration] { return iteration.ElapsedMs(); }, limit - reserve_ms, cost);
  }

  void TransferToLtm(const Stopwatch& iteration, const Hypothesis& hypothesis, Result& result) {
    ScopedTimer timer(&result.times.transfer_ms);
    const TransferTrigger trigger = MakeTransferTrigger(
        options_.memory, iteration.ElapsedMs(), result.times.WmStagesMs(),
        static_cast<int>(memory_.working_memory().size()), dictionary_size_at_start_);
    const Stopwatch stopwatch;
    bool cut_short = false;
    result.transferred_ids =
        Transfer(trigger, retrieved_immune_.InWorkingMemory(memory_), KeptLast(hypothesis), memory_,
                 editor_, DeadlineOf(iteration, &transfer_cost_), &cut_short);
    if ((trigger.time_exceeded && !result.transferred_ids.empty()) || cut_short) {
      result.AddTimeDecision("transfer");
    }
    transfer_step_cost_.Record(stopwatch.ElapsedMs());
  }

  // The hypothesis' WM neighbourhood (around the place it names), retrieved locations included,
  // leaves WM last, so that a place being recognized keeps its neighbours until the filter has
  // decided (memloop; the paper transfers them by weight and age like any other:
  // memory.protect_hypothesis = 0).
  // So do the locations just retrieved (memory.retrieved_kept_last_iterations): the highest
  // hypothesis may be a chance one for an image or two of a revisit.
  std::set<LocationId> KeptLast(const Hypothesis& hypothesis) const {
    std::set<LocationId> kept = retrieved_kept_last_.InWorkingMemory(memory_);
    if (!options_.memory.protect_hypothesis || hypothesis.id == kNoLocation) return kept;
    for (const auto& [id, distance] :
         memory_.WmNeighbourhood(hypothesis.id, options_.filter.neighbour_range)) {
      kept.insert(id);
    }
    return kept;
  }

  // `t` is kNoLocation when localizing: the image made no location.
  void Summarize(LocationId t, const Signature& z_t, const Stopwatch& iteration, Result& result) {
    result.location_id = t;
    result.word_count = z_t.size();
    result.stm_size = static_cast<int>(memory_.stm().size());
    result.wm_size = static_cast<int>(memory_.working_memory().size());
    result.ltm_size = static_cast<int>(ltm_.size());
    result.dictionary_size = static_cast<int>(memory_.dictionary().size());
    result.map_notices = ltm_.TakeNotices();
    for (std::string& notice : fleet_.TakeNotices()) result.map_notices.push_back(notice);
    result.times.ltm_wait_ms = ltm_.TakeWriterWaitMs();
    result.times.ltm_read_ms = ltm_.TakeFileReadMs();
    result.times.cpu_ms = ThreadCpuMs() - iteration_cpu_start_ms_;
    result.times.total_ms = iteration.ElapsedMs();
    signature_budget_.RecordIteration(result.times.total_ms);
    if (result.features_skipped > 0) result.AddTimeDecision("features_skipped");
    if (signature_budget_.searched_coarsely()) result.AddTimeDecision("fewer_checks");
    if (memory_.dictionary().late_steps() != late_steps_at_start_) {
      result.AddTimeDecision("rebuild_late");
    }
  }

  Options options_;
  bool localizing_;                  // memory.localization: the map is read, never changed
  FilterOptions selection_options_;  // options_.filter with T_minHyp within the WM budget
  int skipped_checkpoints_ = 0;
  double iteration_cpu_start_ms_ = 0;  // ThreadCpuMs() at the start of the iteration
  int late_steps_at_start_ = 0;        // the dictionary's late_steps() then
  Stopwatch iteration_;                // since the start of the current image
  bool checkpoint_due_ = false;        // the last image's checkpoint, written by the next
  StepCost transfer_cost_;             // one transfer's
  StepCost transfer_step_cost_;        // the whole transfer step's
  // III-A within the time target: strongest features first (signature_budget.h).
  SignatureBudget signature_budget_{options_.memory, options_.dictionary.search_threads,
                                    [this] { return iteration_.ElapsedMs(); },
                                    options_.dictionary.kd_checks};
  std::unique_ptr<FeatureExtractor> extractor_;
  Memory memory_;
  NeighbourhoodCache wm_neighbourhoods_;  // the filter's, of memory_
  BayesFilter filter_;
  LongTermMemory ltm_;
  RetrievalStep retrieval_;                      // III-E
  std::unique_ptr<AppearanceIndex> appearance_;  // null without retrieval by appearance
  MapEditor editor_;
  DetectorCounters counters_;
  CheckpointWriter checkpoints_;
  bool failed_ = false;
  size_t dictionary_size_at_start_ = 0;
  RecentRetrievals retrieved_immune_{options_.memory.retrieved_immune_iterations};
  RecentRetrievals retrieved_kept_last_{options_.memory.retrieved_kept_last_iterations};
  RolledView rolled_view_;  // surf.rolled_view_degrees: this image's second view
  // This image's own words when Rehearsal gave its location older ones (filter.support_from_image).
  std::optional<Signature> image_words_;
  cv::Mat depth_;             // this image's, in metres; empty without
  DescribedView image_view_;  // this image's keypoints for a loop closure's pose (camera.fx..cy)
  LoopAcceptance acceptance_{options_, memory_, ltm_, appearance_.get()};  // III-D's checks
  bool closed_ = false;
  SessionNumbering sessions_;
  FleetPlaces fleet_;  // a fleet's map: other robots' places, imported
};

Detector::Detector(const Options& options, const std::string& database_path, MapMode mode)
    : impl_(std::make_unique<Impl>(options, database_path, mode)) {}

Detector::~Detector() {
  try {
    impl_->Close();
  } catch (const std::exception&) {
    // A destructor cannot report; Close() reports the same failure to callers that want it.
  }
}

Result Detector::Process(const cv::Mat& image, ImageIndex image_index) {
  ImageInfo info;
  info.index = image_index;
  return impl_->Process(image, cv::Mat(), info);
}
Result Detector::Process(const cv::Mat& image, const ImageInfo& info) {
  return impl_->Process(image, cv::Mat(), info);
}
Result Detector::Process(const cv::Mat& image, const cv::Mat& depth, const ImageInfo& info) {
  return impl_->Process(image, depth, info);
}

void Detector::Flush() { impl_->Flush(); }
size_t Detector::CatchUpWithFleet(double seconds) { return impl_->CatchUpWithFleet(seconds); }
ImageIndex Detector::last_image() const { return impl_->last_image(); }
long long Detector::images_processed() const { return impl_->images_processed(); }
int Detector::session() const { return impl_->session(); }
ImageIndex Detector::session_first_image() const { return impl_->session_first_image(); }
void Detector::SetWriterHeld(bool held) { impl_->SetWriterHeld(held); }
std::vector<std::string> Detector::CheckConsistency() { return impl_->CheckConsistency(); }
void Detector::Close() { impl_->Close(); }
void Detector::CloseAtLastCheckpoint() { impl_->CloseAtLastCheckpoint(); }
const Options& Detector::options() const { return impl_->options(); }

}  // namespace memloop
