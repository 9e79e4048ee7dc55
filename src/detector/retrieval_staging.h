// Retrieval over several iterations (memloop, issue 37; memory.retrieval_over_iterations, T_time
// on with the read-ahead). Re-matching a retrieved location's words that left the dictionary
// (III-E) is a kd-forest search about as long as an image's quantization, which a tight T_time
// rarely leaves room for in one iteration: retrievals were deferred and revisits lost. So a
// location is readied over as many iterations as it takes: its words are searched a chunk at a
// time, beside the next image's feature extraction on another thread (StagedWordSearch: the
// dictionary does not change then, and the other core is mostly idle) and in what the retrieval
// step has left before T_time (SearchStagedWords); the answers are kept here, and the location
// comes back once every word has one. An answer is used only if the word it names is still in
// the dictionary by then (else the word is searched again); a word that matched none is compared
// with the words that joined the dictionary since its search (Dictionary::MatchSince): the next
// images' new words, and words of locations retrieved meanwhile, are the twins re-matching is
// there to find (without this, a revisited place's words came back beside their twins and the next
// images matched neither: 7% of the revisits found instead of 40%). With T_time off nothing is
// staged: a location is retrieved whole, as the paper does.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "detector/step_deadline.h"
#include "storage/long_term_memory.h"
#include "vocabulary/dictionary.h"

namespace memloop {

// A word that left the dictionary, as searched: the word it matched (kNoWord: none), the nearest
// and second distances found (infinity for none), and the dictionary's JoinMark() then.
struct WordAnswer {
  WordId match = kNoWord;
  float nearest = 0;
  float second = 0;
  long long mark = 0;
};
using WordMatches = std::unordered_map<WordId, WordAnswer>;

// The answer of one row of Dictionary::Nearest, searched at `mark`.
WordAnswer AnswerOf(const Dictionary& dictionary, const std::array<Neighbour, 2>& nearest,
                    long long mark);

// The descriptors of `words` (rows in the same order) from LTM (LongTermMemory::LoadWord with
// `rows`); a word LTM does not hold (or holds damaged) is an error naming `location` when
// `required`, else it is left out, and `loaded` (if given) receives the words loaded.
cv::Mat LoadWordDescriptors(const std::vector<WordId>& words, const Dictionary& dictionary,
                            LongTermMemory& ltm, const PrefetchedRows* rows, LocationId location,
                            bool required, std::vector<WordId>* loaded = nullptr);

class RetrievalStaging {
 public:
  struct Staged {
    PrefetchedRows rows;    // as read ahead (words of the location's signature among them)
    WordMatches matches;    // searched so far
    long long touched = 0;  // the last iteration that wanted it
    long long rank = 0;     // its place in what that iteration wanted (Want)
  };
  // A location not wanted for this many iterations is forgotten (the hypothesis moved on).
  static constexpr long long kForgetAfter = 50;
  // A location wanted in one of the last this many iterations is carried on (ContinueStaged).
  static constexpr long long kCarryOnFor = 3;
  // At most this many at once (~65 KB of rows each); the one wanted longest ago goes first.
  static constexpr size_t kMaxStaged = 16;

  Staged* Find(LocationId id);
  Staged& Start(LocationId id, PrefetchedRows rows);
  // This iteration wants `staged`: with `priority` (0 first), then in the order of the calls.
  void Want(Staged& staged, int priority);
  void Erase(LocationId id) { staged_.erase(id); }
  // Counts iterations; forgets what was not wanted for kForgetAfter of them. `join_mark`: the
  // dictionary's JoinMark() now, remembered for JoinMarkBefore.
  void StartIteration(long long join_mark = 0);
  long long iteration() const { return iteration_; }
  // The dictionary's JoinMark() at the start of the iteration `images` before this one (the
  // oldest remembered when that is older: kMarksKept).
  long long JoinMarkBefore(int images) const;
  static constexpr size_t kMarksKept = 32;
  size_t size() const { return staged_.size(); }
  // The staged locations, those this iteration (or the latest) wanted first, in their order.
  std::vector<std::pair<LocationId, Staged*>> ByRecency();

 private:
  std::map<LocationId, Staged> staged_;
  long long iteration_ = 0;
  long long wanted_ = 0;              // Want calls this iteration
  std::deque<long long> join_marks_;  // of the last kMarksKept iterations, the newest last
};

// The words of a staged location's signature (as read ahead) that left the dictionary and have
// no answer yet, with their descriptors (a word renamed since the read has none left: its
// retrieval sees the new name).
std::pair<std::vector<WordId>, cv::Mat> UnsearchedWords(const RetrievalStaging::Staged& staged,
                                                        const Dictionary& dictionary,
                                                        LongTermMemory& ltm);

// Searches the staged location's unsearched words a chunk at a time while `chunk` fits with
// `then_ms` after it (its StepCost learns a chunk's time on one thread), visiting `checks` leaves
// (0: the dictionary's). True when every word has an answer.
bool SearchStagedWords(RetrievalStaging::Staged& staged, const Dictionary& dictionary,
                       LongTermMemory& ltm, const StepDeadline& chunk, double then_ms,
                       int checks = 0);

// The search of staged words beside the image's feature extraction, on a thread of its own: the
// extraction does not touch the dictionary, and searches only read it. Used as
//   { auto running = search.Start(staging, dictionary, ltm); Extract(image); }
// the search stops when `running` goes (at the end of the chunk in flight), before anything
// changes the dictionary, and its answers join their staged locations. A search its thread has
// not begun by then is called off, not waited for: a thread asleep on an idle CPU can be slow to
// wake (in a virtual machine here, 76 ms after it was woken: the image waited as long).
class StagedWordSearch {
 public:
  // At most this many words a search (about an extraction's time on one thread).
  static constexpr size_t kMaxWords = 128;

  // `on_thread_start` runs first on the search's thread (tests hold the thread there).
  explicit StagedWordSearch(std::function<void()> on_thread_start = {});
  ~StagedWordSearch();
  StagedWordSearch(const StagedWordSearch&) = delete;
  StagedWordSearch& operator=(const StagedWordSearch&) = delete;

  class Running {
   public:
    explicit Running(StagedWordSearch* search) : search_(search) {}
    Running(Running&& other) noexcept : search_(std::exchange(other.search_, nullptr)) {}
    Running& operator=(Running&&) = delete;
    ~Running() {
      if (search_ != nullptr) search_->Finish();
    }
    // Waits until every word is searched, as when the extraction outlasts the search (tests).
    void WaitUntilSearched() {
      if (search_ != nullptr) search_->WaitUntilIdle();
    }

   private:
    StagedWordSearch* search_;
  };

  // Starts searching the staged locations' unsearched words, the most recently wanted first
  // (nothing when none is staged), visiting `checks` leaves (0: the dictionary's). Called from
  // the detector's thread.
  [[nodiscard]] Running Start(RetrievalStaging& staging, const Dictionary& dictionary,
                              LongTermMemory& ltm, int checks = 0);
  long long words_searched() const { return words_searched_; }  // since construction

 private:
  void Finish();
  void WaitUntilIdle();
  void Loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  std::atomic<bool> stop_{false};
  bool busy_ = false;
  bool taken_ = false;  // the thread has begun the current search (Finish)
  bool quitting_ = false;
  // The current search: what to search, and for whom.
  const Dictionary* dictionary_ = nullptr;
  cv::Mat descriptors_;
  std::vector<std::pair<LocationId, WordId>> rows_;
  long long mark_ = 0;  // the dictionary's JoinMark() during the search
  int checks_ = 0;
  std::vector<std::array<Neighbour, 2>> found_;
  RetrievalStaging* staging_ = nullptr;
  long long words_searched_ = 0;
  std::thread worker_;
};

}  // namespace memloop
