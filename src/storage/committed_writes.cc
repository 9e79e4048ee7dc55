#include "storage/committed_writes.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

namespace memloop {

void CommittedWrites::Add(long long sequence, Kind kind, int from, int to) {
  writes_.push_back({sequence, kind, from, to});
  while (writes_.size() > capacity_) {
    floor_ = writes_.front().sequence;
    writes_.pop_front();
  }
}

bool CommittedWrites::ReplaySince(long long since, Location& location) const {
  if (since < floor_) return false;
  const auto first = std::upper_bound(
      writes_.begin(), writes_.end(), since,
      [](long long sequence, const Write& write) { return sequence < write.sequence; });
  // Positions of each word in the signature, built at the first rename.
  std::unordered_map<WordId, std::vector<size_t>> positions;
  std::vector<WordId>& words = location.signature.words;
  for (auto write = first; write != writes_.end(); ++write) {
    switch (write->kind) {
      case Kind::kStore:
        if (write->from == location.id) return false;
        break;
      case Kind::kRenameWord: {
        if (positions.empty()) {
          for (size_t k = 0; k < words.size(); ++k) positions[words[k]].push_back(k);
        }
        const auto renamed = positions.find(write->from);
        if (renamed == positions.end()) break;
        std::vector<size_t> moved = std::move(renamed->second);
        positions.erase(renamed);
        for (size_t k : moved) words[k] = write->to;
        auto& target = positions[write->to];
        target.insert(target.end(), moved.begin(), moved.end());
        break;
      }
      case Kind::kRedirect:
        for (auto* links : {&location.neighbours, &location.loop_closures}) {
          if (links->erase(write->from) > 0 && write->to != location.id) links->insert(write->to);
        }
        break;
      case Kind::kNeighbourLink:
      case Kind::kLoopClosureLink:
        if (write->from != location.id || write->to == location.id) break;
        (write->kind == Kind::kLoopClosureLink ? location.loop_closures : location.neighbours)
            .insert(write->to);
        break;
    }
  }
  return true;
}

}  // namespace memloop
