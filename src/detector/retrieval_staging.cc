#include "detector/retrieval_staging.h"

#include <algorithm>
#include <limits>

#include "detector/stopwatch.h"
#include "memloop/errors.h"
#include "util/thread_name.h"
#include "vocabulary/word_index.h"

namespace memloop {

cv::Mat LoadWordDescriptors(const std::vector<WordId>& words, const Dictionary& dictionary,
                            LongTermMemory& ltm, const PrefetchedRows* rows, LocationId location,
                            bool required, std::vector<WordId>* loaded) {
  cv::Mat descriptors(static_cast<int>(words.size()), dictionary.descriptor_dim(),
                      dictionary.descriptor_cv_type());
  const size_t row_bytes = descriptors.cols * descriptors.elemSize();
  int filled = 0;
  for (WordId word : words) {
    const auto descriptor = ltm.LoadWord(word, rows);
    if (!descriptor || descriptor->size() != row_bytes) {
      if (!required) continue;
      throw DatabaseError(ltm.path(), "word " + std::to_string(word) + " of location " +
                                          std::to_string(location) + " is missing or damaged");
    }
    std::copy(descriptor->begin(), descriptor->end(), descriptors.ptr<unsigned char>(filled++));
    if (loaded != nullptr) loaded->push_back(word);
  }
  return descriptors.rowRange(0, filled);
}

RetrievalStaging::Staged* RetrievalStaging::Find(LocationId id) {
  const auto found = staged_.find(id);
  return found == staged_.end() ? nullptr : &found->second;
}

RetrievalStaging::Staged& RetrievalStaging::Start(LocationId id, PrefetchedRows rows) {
  if (staged_.size() >= kMaxStaged && staged_.count(id) == 0) {
    const auto oldest = std::min_element(
        staged_.begin(), staged_.end(),
        [](const auto& a, const auto& b) { return a.second.touched < b.second.touched; });
    staged_.erase(oldest);
  }
  Staged& staged = staged_[id];
  staged.rows = std::move(rows);
  staged.matches.clear();
  staged.touched = iteration_;
  return staged;
}

void RetrievalStaging::Want(Staged& staged, int priority) {
  staged.touched = iteration_;
  staged.rank = (static_cast<long long>(priority) << 32) + wanted_++;
}

void RetrievalStaging::StartIteration(long long join_mark) {
  ++iteration_;
  wanted_ = 0;
  join_marks_.push_back(join_mark);
  if (join_marks_.size() > kMarksKept) join_marks_.pop_front();
  for (auto entry = staged_.begin(); entry != staged_.end();) {
    entry =
        iteration_ - entry->second.touched > kForgetAfter ? staged_.erase(entry) : std::next(entry);
  }
}

long long RetrievalStaging::JoinMarkBefore(int images) const {
  if (join_marks_.empty()) return 0;
  const size_t back = std::min(join_marks_.size() - 1, static_cast<size_t>(std::max(0, images)));
  return join_marks_[join_marks_.size() - 1 - back];  // back() is this iteration's
}

std::vector<std::pair<LocationId, RetrievalStaging::Staged*>> RetrievalStaging::ByRecency() {
  std::vector<std::pair<LocationId, Staged*>> staged;
  for (auto& [id, entry] : staged_) staged.emplace_back(id, &entry);
  std::stable_sort(staged.begin(), staged.end(), [](const auto& a, const auto& b) {
    if (a.second->touched != b.second->touched) return a.second->touched > b.second->touched;
    return a.second->rank < b.second->rank;
  });
  return staged;
}

std::pair<std::vector<WordId>, cv::Mat> UnsearchedWords(const RetrievalStaging::Staged& staged,
                                                        const Dictionary& dictionary,
                                                        LongTermMemory& ltm) {
  std::vector<WordId> unsearched;
  if (!staged.rows.location) return {};  // nothing read: its retrieval reports the problem
  for (const auto& [word, count] : staged.rows.location->signature.Histogram()) {
    if (!dictionary.Contains(word) && staged.matches.count(word) == 0) unsearched.push_back(word);
  }
  std::vector<WordId> words;
  cv::Mat descriptors = LoadWordDescriptors(unsearched, dictionary, ltm, &staged.rows,
                                            staged.rows.location->id, /*required=*/false, &words);
  return {std::move(words), std::move(descriptors)};
}

WordAnswer AnswerOf(const Dictionary& dictionary, const std::array<Neighbour, 2>& nearest,
                    long long mark) {
  constexpr float kNone = std::numeric_limits<float>::max();
  WordAnswer answer;
  answer.match = dictionary.MatchOf(nearest);
  answer.nearest = nearest[0].word != kNoWord ? nearest[0].distance : kNone;
  answer.second = nearest[1].word != kNoWord ? nearest[1].distance : kNone;
  answer.mark = mark;
  return answer;
}

bool SearchStagedWords(RetrievalStaging::Staged& staged, const Dictionary& dictionary,
                       LongTermMemory& ltm, const StepDeadline& chunk, double then_ms, int checks) {
  const auto [words, descriptors] = UnsearchedWords(staged, dictionary, ltm);
  if (words.empty()) return true;
  if (!chunk.Fits(then_ms)) return false;
  const Stopwatch stopwatch;
  const long long mark = dictionary.JoinMark();
  const auto found =
      dictionary.Nearest(descriptors, {[&](size_t) { return chunk.Fits(then_ms); }, false, checks});
  // One chunk on one thread: a search of more than one chunk is shared by the threads.
  const size_t threads = found.size() > WordIndex::kSearchChunk ? dictionary.search_threads() : 1;
  chunk.Record(stopwatch.ElapsedMs() * threads * WordIndex::kSearchChunk / found.size());
  for (size_t i = 0; i < found.size(); ++i) {
    staged.matches[words[i]] = AnswerOf(dictionary, found[i], mark);
  }
  return found.size() == words.size();
}

StagedWordSearch::StagedWordSearch(std::function<void()> on_thread_start)
    : worker_([this, on_thread_start = std::move(on_thread_start)] {
        if (on_thread_start) on_thread_start();
        Loop();
      }) {}

StagedWordSearch::~StagedWordSearch() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quitting_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

StagedWordSearch::Running StagedWordSearch::Start(RetrievalStaging& staging,
                                                  const Dictionary& dictionary, LongTermMemory& ltm,
                                                  int checks) {
  std::vector<std::pair<LocationId, WordId>> rows;
  cv::Mat descriptors;
  for (const auto& [id, staged] : staging.ByRecency()) {
    if (rows.size() >= kMaxWords) break;
    auto [words, location_descriptors] = UnsearchedWords(*staged, dictionary, ltm);
    const size_t take = std::min(words.size(), kMaxWords - rows.size());
    for (size_t i = 0; i < take; ++i) rows.emplace_back(id, words[i]);
    if (take > 0) descriptors.push_back(location_descriptors.rowRange(0, static_cast<int>(take)));
  }
  if (rows.empty()) return Running(nullptr);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dictionary_ = &dictionary;
    descriptors_ = descriptors;
    rows_ = std::move(rows);
    mark_ = dictionary.JoinMark();
    checks_ = checks;
    staging_ = &staging;
    found_.clear();
    stop_ = false;
    busy_ = true;
    taken_ = false;
  }
  wake_.notify_all();
  return Running(this);
}

void StagedWordSearch::Finish() {
  stop_ = true;
  std::unique_lock<std::mutex> lock(mutex_);
  if (busy_ && !taken_) {  // not begun: called off
    busy_ = false;
    found_.clear();
  }
  done_.wait(lock, [this] { return !busy_; });
  for (size_t i = 0; i < found_.size(); ++i) {
    RetrievalStaging::Staged* staged = staging_->Find(rows_[i].first);
    if (staged != nullptr) {
      staged->matches[rows_[i].second] = AnswerOf(*dictionary_, found_[i], mark_);
    }
  }
  words_searched_ += static_cast<long long>(found_.size());
  dictionary_ = nullptr;
  staging_ = nullptr;
}

void StagedWordSearch::WaitUntilIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return !busy_; });
}

void StagedWordSearch::Loop() {
  NameThisThread("staging");
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return quitting_ || busy_; });
    if (quitting_) return;
    taken_ = true;
    const Dictionary* dictionary = dictionary_;
    const cv::Mat descriptors = descriptors_;
    const int checks = checks_;
    lock.unlock();
    std::vector<std::array<Neighbour, 2>> found;
    try {
      // The first chunk is searched whatever the gate: not when stopped before it began.
      if (!stop_) {
        found = dictionary->Nearest(
            descriptors, {[this](size_t) { return !stop_; }, /*caller_only=*/true, checks});
      }
    } catch (const std::exception&) {
      found.clear();  // the words are searched again at their retrieval, which reports a problem
    }
    lock.lock();
    found_ = std::move(found);
    busy_ = false;
    done_.notify_all();
  }
}

}  // namespace memloop
