#include "detector/checkpoint.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <string_view>
#include <type_traits>

#include "memloop/errors.h"

namespace memloop {
namespace {

// Blobs are the machine's byte order of fixed-width values (a map resumes on the machine kind
// that wrote it; LTM's own tables are plain SQL values).
class ByteWriter {
 public:
  template <typename T>
  ByteWriter& Put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* data = reinterpret_cast<const unsigned char*>(&value);
    bytes_.insert(bytes_.end(), data, data + sizeof(T));
    return *this;
  }
  template <typename Range>
  ByteWriter& PutAll(const Range& values) {
    Put(static_cast<uint64_t>(values.size()));
    for (const auto& value : values) Put(value);
    return *this;
  }
  // A vector in one copy (a rebuild's snapshot is up to millions of word ids).
  template <typename T>
  ByteWriter& PutAll(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    Put(static_cast<uint64_t>(values.size()));
    const auto* data = reinterpret_cast<const unsigned char*>(values.data());
    bytes_.insert(bytes_.end(), data, data + values.size() * sizeof(T));
    return *this;
  }
  std::vector<unsigned char> Take() { return std::move(bytes_); }

 private:
  std::vector<unsigned char> bytes_;
};

class ByteReader {
 public:
  ByteReader(const std::vector<unsigned char>& bytes, std::string what)
      : bytes_(bytes), what_(std::move(what)) {}
  template <typename T>
  T Get() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (bytes_.size() - position_ < sizeof(T)) throw Error(what_ + " is truncated");
    T value;
    std::memcpy(&value, bytes_.data() + position_, sizeof(T));
    position_ += sizeof(T);
    return value;
  }
  // A count of items of `item_bytes` each, checked against the bytes left.
  bool AtEnd() const { return position_ == bytes_.size(); }
  size_t Count(size_t item_bytes) {
    const auto count = Get<uint64_t>();
    if (count > (bytes_.size() - position_) / std::max<size_t>(item_bytes, 1)) {
      throw Error(what_ + " is truncated");
    }
    return static_cast<size_t>(count);
  }
  template <typename T>
  std::vector<T> GetAll() {
    std::vector<T> values(Count(sizeof(T)));
    for (T& value : values) value = Get<T>();
    return values;
  }
  void ExpectEnd() const {
    if (position_ != bytes_.size()) throw Error(what_ + " has trailing bytes");
  }

 private:
  const std::vector<unsigned char>& bytes_;
  std::string what_;
  size_t position_ = 0;
};

size_t Hash(const std::vector<unsigned char>& bytes) {
  return std::hash<std::string_view>()(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

// Keys of the resume_state table.
constexpr const char* kCounters = "counters";
constexpr const char* kStm = "stm";
// LTM's marks on the dictionary's words: one key per chunk of WordBitset::kChunkIds word ids.
std::string MarksKey(size_t chunk) { return "word_marks." + std::to_string(chunk); }
// Maps of format 4-5 hold them by chunks of 65,536 ids, under other keys; a full checkpoint (the
// first of a session) deletes these and writes the new ones.
constexpr size_t kFormat5MarkChunkIds = 65536;
std::string Format5MarksKey(size_t chunk) { return "ltm_marks." + std::to_string(chunk); }
constexpr const char* kIndex = "index";
constexpr const char* kIndexPending = "index_pending";             // empty: no background build
constexpr const char* kIndexPendingWords = "index_pending_words";  // its snapshot, once per build
constexpr const char* kFilter = "filter";
constexpr const char* kPastMatches = "past_matches";
// Absent from maps written before retrieved_kept_last_iterations (2026-12-05): none.
constexpr const char* kKeptLast = "retrieved_kept_last";
// Absent from maps written before filter.cap_merged_images (2026-12-05): 0.
constexpr const char* kPreviousValue = "previous_hypothesis_value";

}  // namespace

std::vector<unsigned char> EncodeLocation(const Location& location) {
  ByteWriter writer;
  writer.Put<int32_t>(location.id).Put<int32_t>(location.weight);
  writer.PutAll(location.images).PutAll(location.neighbours).PutAll(location.loop_closures);
  const Signature& signature = location.signature;
  writer.Put(static_cast<uint64_t>(signature.words.size()));
  for (size_t k = 0; k < signature.words.size(); ++k) {
    const cv::KeyPoint& keypoint = signature.keypoints[k];
    writer.Put<int32_t>(signature.words[k]).Put(keypoint.pt.x).Put(keypoint.pt.y);
    writer.Put(keypoint.size).Put(keypoint.angle).Put(keypoint.response);
    writer.Put<int32_t>(keypoint.octave);
  }
  writer.Put<int32_t>(signature.image);
  // Only when there is one: without features.whole_image the bytes are those of format 5.
  if (!signature.whole_image.empty()) writer.PutAll(signature.whole_image);
  return writer.Take();
}

Location DecodeLocation(const std::vector<unsigned char>& bytes) {
  ByteReader reader(bytes, "a location of the checkpoint");
  Location location;
  location.id = reader.Get<int32_t>();
  location.weight = reader.Get<int32_t>();
  location.images = reader.GetAll<ImageIndex>();
  for (LocationId id : reader.GetAll<LocationId>()) location.neighbours.insert(id);
  for (LocationId id : reader.GetAll<LocationId>()) location.loop_closures.insert(id);
  const size_t words = reader.Count(28);
  for (size_t k = 0; k < words; ++k) {
    location.signature.words.push_back(reader.Get<int32_t>());
    const float x = reader.Get<float>();
    const float y = reader.Get<float>();
    const float size = reader.Get<float>();
    const float angle = reader.Get<float>();
    const float response = reader.Get<float>();
    location.signature.keypoints.emplace_back(cv::Point2f(x, y), size, angle, response,
                                              reader.Get<int32_t>());
  }
  // Checkpoints written before the signature's image was kept end here; before its whole-image
  // descriptor, after the image.
  if (!reader.AtEnd()) location.signature.image = reader.Get<int32_t>();
  if (!reader.AtEnd()) location.signature.whole_image = reader.GetAll<uint8_t>();
  reader.ExpectEnd();
  return location;
}

void CheckpointWriter::AddState(CheckpointData& checkpoint, const std::string& key,
                                std::vector<unsigned char> value) {
  const size_t hash = Hash(value);
  const auto written = state_hashes_.find(key);
  if (!first_ && written != state_hashes_.end() && written->second == hash) return;
  state_hashes_[key] = hash;
  checkpoint.state.emplace_back(key, std::move(value));
}

CheckpointData CheckpointWriter::Next(const Memory& memory, const BayesFilter& filter,
                                      const std::vector<PastMatch>& past_matches,
                                      const DetectorCounters& counters,
                                      const RecentRetrievals& kept_last) {
  CheckpointData checkpoint;
  checkpoint.full = first_;
  // Locations: written when new or changed, removed when they left memory. Only those Memory
  // gave out mutably, added, restored or removed since it was last cleared can have changed: the
  // others are not encoded again (issue 9: docs/design.md, "The cost", measures it), nor looked
  // at (a lookup per WM location was 0.4 ms of a checkpoint at WM 2,000).
  const auto encode = [&](LocationId id) {
    std::vector<unsigned char> data = EncodeLocation(memory.at(id));
    const size_t hash = Hash(data);
    auto written = location_hashes_.find(id);
    if (!first_ && written != location_hashes_.end() && written->second == hash) return;
    location_hashes_[id] = hash;
    checkpoint.locations.emplace_back(id, std::move(data));
  };
  if (first_) {
    location_hashes_.clear();
    for (const auto& [id, location] : memory.locations()) encode(id);
  } else {
    for (LocationId id : memory.changed()) {  // in id order
      if (memory.Contains(id)) {
        encode(id);
      } else if (location_hashes_.erase(id) > 0) {
        checkpoint.removed_locations.push_back(id);
      }
    }
  }

  // The forest: points added since the previous checkpoint, or all of them after a rebuild, as
  // word ids; a word's descriptor (it never changes) is written once, with its first point. A
  // rebuild thus rewrites one blob of word ids, not the descriptors (issue 9: it was a 250 ms
  // pause at 160,000 words).
  const Dictionary& dictionary = memory.dictionary();
  const WordIndex& index = dictionary.index();
  IndexHistory history = index.History(index_points_written_, /*complete=*/false);
  checkpoint.reset_index = first_ || history.build_count != index_build_count_ ||
                           history.point_count < index_points_written_;
  if (checkpoint.reset_index) {
    history = index.History(0, /*complete=*/false);
    if (first_) {  // the file's descriptors all go
      descriptors_written_.Clear();
      descriptors_to_forget_.Clear();
    }
    // Descriptors the new points no longer name are deleted later, a few at a time, so that the
    // writer (which the next checkpoint waits for) is not held up.
    WordBitset named;
    for (WordId word : history.point_words) named.Insert(word);
    descriptors_written_.MoveAbsentFrom(named, descriptors_to_forget_);
  }
  checkpoint.first_index_point = static_cast<long long>(history.first_point);
  for (size_t k = 0; k < history.point_words.size(); ++k) {
    const WordId word = history.point_words[k];
    if (!descriptors_written_.Insert(word)) continue;
    const cv::Mat row = index.PointDescriptor(history.first_point + k);
    checkpoint.index_descriptors.emplace_back(
        word, std::vector<unsigned char>(row.data, row.data + row.total() * row.elemSize()));
    descriptors_to_forget_.Erase(word);  // written again: it must stay
  }
  checkpoint.index_words = std::move(history.point_words);
  constexpr size_t kForgottenPerCheckpoint = 2000;
  checkpoint.forgotten_descriptors = descriptors_to_forget_.TakeSmallest(kForgottenPerCheckpoint);
  index_build_count_ = history.build_count;
  index_points_written_ = history.point_count;

  AddState(checkpoint, kCounters,
           ByteWriter()
               .Put<int32_t>(counters.last_image)
               .Put<int64_t>(counters.images_processed)
               .Put<int32_t>(counters.newest_location)
               .Put<int32_t>(memory.next_id())
               .Put<int32_t>(dictionary.next_word_id())
               .Take());
  AddState(checkpoint, kStm, ByteWriter().PutAll(memory.stm()).Take());
  // The marks: every chunk in a full checkpoint, then only those whose marks changed (issue 9:
  // the list of all marked words, 730 KB at 180,000 marks, was encoded, hashed and written again
  // at every image that transferred a location).
  const WordBitset& marks = dictionary.ltm_marks();
  const auto put_marks = [&](size_t chunk) {
    checkpoint.state.emplace_back(MarksKey(chunk),
                                  ByteWriter().PutAll(marks.ChunkBlocks(chunk)).Take());
  };
  if (first_) {
    for (size_t chunk = 0; chunk < marks.chunk_count(); ++chunk) put_marks(chunk);
  } else {
    for (size_t chunk : dictionary.changed_mark_chunks()) put_marks(chunk);
  }
  ByteWriter index_state;
  index_state.Put<int32_t>(history.build_count)
      .Put<uint64_t>(history.size_at_build)
      .Put<uint64_t>(history.changes_since_build)
      .Put<uint64_t>(history.point_count);
  std::vector<uint64_t> starts(history.batch_starts.begin(), history.batch_starts.end());
  AddState(checkpoint, kIndex, index_state.PutAll(starts).Take());
  // A background build: its age changes at every image, its words (the snapshot, up to millions)
  // only when a new build starts, so they are written apart, once.
  ByteWriter pending;
  if (history.pending) {
    pending.Put<uint64_t>(history.pending_point).Put<int32_t>(history.pending_age);
    const std::pair<int, size_t> build{history.build_count, history.pending_point};
    if (first_ || build != pending_words_written_) {
      AddState(checkpoint, kIndexPendingWords, ByteWriter().PutAll(index.PendingWords()).Take());
      pending_words_written_ = build;
    }
  }
  AddState(checkpoint, kIndexPending, pending.Take());
  ByteWriter filter_state;
  filter_state.Put(filter.virtual_place()).Put(static_cast<uint64_t>(filter.posterior().size()));
  for (const auto& [id, probability] : filter.posterior()) {
    filter_state.Put<int32_t>(id).Put(probability);
  }
  AddState(checkpoint, kFilter, filter_state.Take());
  ByteWriter matches;
  matches.Put(static_cast<uint64_t>(past_matches.size()));
  for (const PastMatch& match : past_matches) {
    matches.Put<int32_t>(match.matched).Put<int32_t>(match.matcher);
  }
  AddState(checkpoint, kPastMatches, matches.Take());
  ByteWriter retrieved;
  retrieved.Put(static_cast<uint64_t>(kept_last.retrieved_at().size()));
  for (const auto& [id, iteration] : kept_last.retrieved_at()) {
    retrieved.Put<int32_t>(id).Put<int64_t>(iteration);
  }
  AddState(checkpoint, kKeptLast, retrieved.Take());
  AddState(checkpoint, kPreviousValue, ByteWriter().Put(counters.previous_hypothesis_value).Take());
  first_ = false;
  return checkpoint;
}

namespace {

std::vector<unsigned char> RequiredState(LtmDatabase& database, const std::string& key) {
  std::optional<std::vector<unsigned char>> value = database.ReadState(key);
  if (!value) throw Error("its checkpoint has no '" + key + "' entry");
  return std::move(*value);
}

// How the dictionary's descriptors are stored: one row of `dim` elements of OpenCV type `cv_type`.
struct DescriptorFormat {
  int dim = 0;
  int cv_type = 0;
};

void ReadIndex(LtmDatabase& database, std::optional<DescriptorFormat> format, ResumeState& state) {
  const std::vector<unsigned char> bytes = RequiredState(database, kIndex);
  ByteReader reader(bytes, "the checkpoint's index entry");
  IndexHistory& index = state.index;
  index.build_count = reader.Get<int32_t>();
  index.size_at_build = reader.Get<uint64_t>();
  index.changes_since_build = reader.Get<uint64_t>();
  index.point_count = reader.Get<uint64_t>();
  for (uint64_t start : reader.GetAll<uint64_t>()) index.batch_starts.push_back(start);
  reader.ExpectEnd();
  // Maps written before background rebuilds have no such entry.
  const std::optional<std::vector<unsigned char>> pending = database.ReadState(kIndexPending);
  if (pending && !pending->empty()) {
    ByteReader pending_reader(*pending, "the checkpoint's pending index build");
    index.pending = true;
    index.pending_point = pending_reader.Get<uint64_t>();
    index.pending_age = pending_reader.Get<int32_t>();
    pending_reader.ExpectEnd();
    const std::vector<unsigned char> words = RequiredState(database, kIndexPendingWords);
    ByteReader words_reader(words, "the checkpoint's pending index build");
    index.pending_words = words_reader.GetAll<WordId>();
    words_reader.ExpectEnd();
  }
  const std::vector<CheckpointData::Point> points =
      database.ReadIndexPoints();  // descriptors joined
  if (points.size() != index.point_count) throw Error("its checkpoint's index points are missing");
  // Without the dictionary (inspect), every row must be as long as the first.
  if (!format)
    format =
        DescriptorFormat{points.empty() ? 1 : static_cast<int>(points[0].descriptor.size()), CV_8U};
  const size_t row_bytes = static_cast<size_t>(format->dim) * CV_ELEM_SIZE(format->cv_type);
  index.descriptors.create(static_cast<int>(points.size()), format->dim, format->cv_type);
  for (size_t k = 0; k < points.size(); ++k) {
    if (points[k].point != static_cast<long long>(k) || points[k].descriptor.size() != row_bytes) {
      throw Error("index point " + std::to_string(points[k].point) +
                  " of its checkpoint is damaged");
    }
    index.point_words.push_back(points[k].word);
    std::memcpy(index.descriptors.ptr(static_cast<int>(k)), points[k].descriptor.data(), row_bytes);
  }
}

// The marks stored by chunks of `chunk_ids` ids under `key`(chunk), appended to `ids`. Chunks
// can only hold ids the dictionary gave; an absent chunk holds none.
void ReadMarks(LtmDatabase& database, WordId next_word_id, std::string (*key)(size_t),
               size_t chunk_ids, std::vector<WordId>& ids) {
  const size_t chunks =
      (static_cast<size_t>(std::max<WordId>(next_word_id, 1)) - 1) / chunk_ids + 1;
  for (size_t chunk = 0; chunk < chunks; ++chunk) {
    const std::optional<std::vector<unsigned char>> bytes = database.ReadState(key(chunk));
    if (!bytes) continue;
    ByteReader reader(*bytes, "the checkpoint's dictionary marks");
    const std::vector<uint64_t> blocks = reader.GetAll<uint64_t>();
    reader.ExpectEnd();
    if (blocks.size() > chunk_ids / 64) throw Error("a chunk of marks is too long");
    WordBitset::AppendChunkIds(chunk, blocks, ids, chunk_ids);
  }
}

void ReadCounters(const std::vector<unsigned char>& bytes, ResumeState& state) {
  ByteReader reader(bytes, "the checkpoint's counters");
  state.counters.last_image = reader.Get<int32_t>();
  state.counters.images_processed = reader.Get<int64_t>();
  state.counters.newest_location = reader.Get<int32_t>();
  state.next_location_id = reader.Get<int32_t>();
  state.next_word_id = reader.Get<int32_t>();
  reader.ExpectEnd();
}

ResumeState ReadState(LtmDatabase& database, std::optional<DescriptorFormat> format) {
  ResumeState state;
  ReadCounters(RequiredState(database, kCounters), state);
  {
    const std::vector<unsigned char> bytes = RequiredState(database, kStm);
    ByteReader reader(bytes, "the checkpoint's STM");
    for (LocationId id : reader.GetAll<LocationId>()) state.stm.push_back(id);
    reader.ExpectEnd();
  }
  ReadMarks(database, state.next_word_id, MarksKey, WordBitset::kChunkIds,
            state.words_referenced_by_ltm);
  ReadMarks(database, state.next_word_id, Format5MarksKey, kFormat5MarkChunkIds,
            state.words_referenced_by_ltm);
  ReadIndex(database, format, state);
  {
    const std::vector<unsigned char> bytes = RequiredState(database, kFilter);
    ByteReader reader(bytes, "the checkpoint's filter");
    state.virtual_place = reader.Get<double>();
    const size_t count = reader.Count(12);
    for (size_t k = 0; k < count; ++k) {
      const auto id = reader.Get<int32_t>();
      state.posterior[id] = reader.Get<double>();
    }
    reader.ExpectEnd();
  }
  {
    const std::vector<unsigned char> bytes = RequiredState(database, kPastMatches);
    ByteReader reader(bytes, "the checkpoint's past matches");
    const size_t count = reader.Count(8);
    for (size_t k = 0; k < count; ++k) {
      PastMatch match;
      match.matched = reader.Get<int32_t>();
      match.matcher = reader.Get<int32_t>();
      state.past_matches.push_back(match);
    }
    reader.ExpectEnd();
  }
  if (const std::optional<std::vector<unsigned char>> bytes = database.ReadState(kKeptLast)) {
    ByteReader reader(*bytes, "the checkpoint's retrieved locations");
    const size_t count = reader.Count(12);
    for (size_t k = 0; k < count; ++k) {
      const auto id = reader.Get<int32_t>();
      state.kept_last[id] = reader.Get<int64_t>();
    }
    reader.ExpectEnd();
  }
  if (const std::optional<std::vector<unsigned char>> bytes = database.ReadState(kPreviousValue)) {
    ByteReader reader(*bytes, "the checkpoint's previous hypothesis value");
    state.counters.previous_hypothesis_value = reader.Get<double>();
    reader.ExpectEnd();
  }
  std::set<WordId> words;
  for (const auto& [id, data] : database.ReadMemoryLocations()) {
    Location location = DecodeLocation(data);
    if (location.id != id) throw Error("location row " + std::to_string(id) + " is damaged");
    words.insert(location.signature.words.begin(), location.signature.words.end());
    state.locations.emplace(id, std::move(location));
  }
  state.words.assign(words.begin(), words.end());
  return state;
}

}  // namespace

ResumeState ReadCheckpoint(LtmDatabase& database, const Dictionary& dictionary,
                           const std::string& use) {
  if (database.format_version() < LtmDatabase::kOldestResumable) {
    throw DatabaseError(database.path(),
                        "this map was made by an older memloop (map format " +
                            std::to_string(database.format_version()) +
                            ") whose resume checkpoint this one does not read; it cannot be "
                            "resumed (its LTM can still be read)");
  }
  if (!database.ReadState(kCounters)) {
    throw DatabaseError(database.path(),
                        "has no resume checkpoint (the run that made it stopped before its first "
                        "one was committed): start a new map instead");
  }
  try {
    return ReadState(
        database, DescriptorFormat{dictionary.descriptor_dim(), dictionary.descriptor_cv_type()});
  } catch (const DatabaseError&) {
    throw;
  } catch (const Error& error) {
    throw DatabaseError(database.path(),
                        "cannot " + use + ": the map is damaged (" + error.what() + ")");
  }
}

DetectorCounters RestoreCheckpoint(LtmDatabase& database, Memory& memory, BayesFilter& filter,
                                   MapEditor& editor, RecentRetrievals& kept_last,
                                   const std::string& use) {
  ResumeState state = ReadCheckpoint(database, memory.dictionary(), use);
  try {
    memory.dictionary().Reload(state.words, state.index, state.words_referenced_by_ltm,
                               state.next_word_id);
    memory.Reload(std::move(state.locations), state.stm, state.next_location_id);
  } catch (const DatabaseError&) {
    throw;
  } catch (const Error& error) {
    throw DatabaseError(database.path(),
                        "cannot " + use + ": the map is damaged (" + error.what() + ")");
  }
  filter.Reload(std::move(state.posterior), state.virtual_place);
  editor.SetPastMatches(std::move(state.past_matches));
  kept_last.Reload(std::move(state.kept_last));
  return state.counters;
}

std::optional<DetectorCounters> ReadCheckpointCounters(LtmDatabase& database) {
  const std::optional<std::vector<unsigned char>> bytes = database.ReadState(kCounters);
  if (!bytes) return std::nullopt;
  ResumeState state;
  try {
    ReadCounters(*bytes, state);
  } catch (const Error& error) {
    throw DatabaseError(database.path(), std::string("the map is damaged (") + error.what() + ")");
  }
  return state.counters;
}

bool MapHoldsNoImage(LtmDatabase& database) {
  try {
    return database.format_version() == LtmDatabase::kFormatVersion &&
           !ReadCheckpointCounters(database) && database.CountLocations() == 0 &&
           database.QueryNumber("SELECT count(*) FROM location_images") == 0;
  } catch (const DatabaseError&) {
    return false;
  }
}

std::string CheckpointProblem(LtmDatabase& database) {
  if (database.format_version() < LtmDatabase::kOldestResumable) return "";  // not resumable anyway
  if (!database.ReadState(kCounters)) return "";
  try {
    ReadState(database, std::nullopt);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

}  // namespace memloop
