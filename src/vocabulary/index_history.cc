#include "vocabulary/index_history.h"

#include <algorithm>

#include "memloop/errors.h"

namespace memloop {

void CheckIndexHistory(const IndexHistory& history, int dim, int cv_type) {
  bool valid = history.first_point == 0 && history.point_words.size() == history.point_count &&
               static_cast<size_t>(history.descriptors.rows) == history.point_count &&
               (history.point_count == 0 ||
                (history.descriptors.type() == cv_type && history.descriptors.cols == dim &&
                 history.descriptors.isContinuous())) &&
               (history.point_count == 0) == history.batch_starts.empty();
  for (size_t batch = 0; valid && batch < history.batch_starts.size(); ++batch) {
    const size_t start = history.batch_starts[batch];
    valid = start < history.point_count &&
            (batch == 0 ? start == 0 : start > history.batch_starts[batch - 1]);
  }
  valid = valid && (!history.pending ||
                    (history.pending_point <= history.point_count && history.pending_age >= 0 &&
                     std::is_sorted(history.pending_words.begin(), history.pending_words.end())));
  if (!valid) throw Error("the dictionary's index history is inconsistent");
}

LatestPoints LatestPointsOf(const IndexHistory& history) {
  LatestPoints latest;
  for (size_t point = 0; point < history.point_count; ++point) {
    latest.overall[history.point_words[point]] = point;
    if (history.pending && point < history.pending_point) {
      latest.before_pending[history.point_words[point]] = point;
    }
  }
  return latest;
}

}  // namespace memloop
