#include "memloop/place_sequence.h"

#include <cmath>

#include "memloop/errors.h"
#include "synthetic/synthetic_view.h"

namespace memloop {

PlaceSequence::PlaceSequence(const PlaceSequenceOptions& options) : options_(options) {
  const auto require = [](bool valid, const std::string& what) {
    if (!valid) throw InputError("generated sequence", what);
  };
  require(options.places >= 1, "places must be >= 1");
  require(options.frames_per_place >= 1, "frames per place must be >= 1");
  require(options.revisit_every >= 0, "revisit_every must be >= 0");
  require(options.min_revisit_age >= 0, "min_revisit_age must be >= 0");
  require(options.image_width >= 32 && options.image_height >= 32, "images must be >= 32x32");
  require(static_cast<double>(options.places) * options.frames_per_place < 1e8,
          "more than 100 million frames");
  cv::RNG rng(static_cast<uint64_t>(options.seed) * 7919u + 1);
  visits_of_place_.resize(options.places);
  std::vector<int> last_seen(options.places, -1);  // the frame after the last visit
  int visit = 0;
  const auto add_visit = [&](int place) {
    visits_of_place_[place].push_back(size());
    for (int offset = 0; offset < options.frames_per_place; ++offset) {
      const ViewJitter j = ViewJitter::Random(rng);
      frames_.push_back(
          {place, visit, offset, j.dx, j.dy, j.scale, j.angle_degrees, j.gain, j.bias});
    }
    last_seen[place] = size();
    ++visit;
  };
  for (int place = 0; place < options.places; ++place) {
    add_visit(place);
    if (options.revisit_every == 0 || (place + 1) % options.revisit_every != 0) continue;
    std::vector<int> candidates;
    for (int earlier = 0; earlier < place; ++earlier) {
      if (size() - last_seen[earlier] >= options.min_revisit_age) candidates.push_back(earlier);
    }
    if (candidates.empty()) continue;
    add_visit(candidates[rng.uniform(0, static_cast<int>(candidates.size()))]);
    ++revisits_;
  }
}

cv::Mat PlaceSequence::PlaceTexture(int place) const {
  // cached_texture_ is shared: the caller holds cache_mutex_.
  if (cached_place_ != place) {
    cv::RNG rng(static_cast<uint64_t>(options_.seed) * 1000003u + static_cast<uint64_t>(place));
    const int width =
        static_cast<int>(std::ceil((options_.frames_per_place - 1) * options_.step_px)) +
        2 * options_.image_width;
    cached_texture_ = MakeTexture(width, options_.image_height + 60, rng);
    cached_place_ = place;
  }
  return cached_texture_;
}

cv::Mat PlaceSequence::Render(int index) const {
  const Frame& frame = frames_.at(index);
  const ViewJitter jitter{frame.dx,   frame.dy,  frame.scale, frame.angle_degrees,
                          frame.gain, frame.bias};
  const std::lock_guard<std::mutex> lock(cache_mutex_);
  return RenderView(PlaceTexture(frame.place),
                    options_.image_width / 2.0 + frame.offset * options_.step_px, 30, jitter,
                    options_.image_width, options_.image_height,
                    static_cast<uint64_t>(options_.seed) * 999983u + static_cast<uint64_t>(index));
}

bool PlaceSequence::IsLoop(int query, int match) const {
  const Frame& a = frames_.at(query);
  const Frame& b = frames_.at(match);
  if (match >= query || a.place != b.place || a.visit == b.visit) return false;
  const double distance =
      std::fabs((a.offset * options_.step_px + a.dx) - (b.offset * options_.step_px + b.dx));
  return distance <= options_.same_place_fraction * options_.image_width;
}

std::vector<std::pair<int, int>> PlaceSequence::GroundTruthPairs() const {
  std::vector<std::pair<int, int>> pairs;
  for (int query = 0; query < size(); ++query) {
    // Only earlier visits of the same place can match.
    for (int first : visits_of_place_[frames_[query].place]) {
      if (first >= query) break;
      for (int match = first; match < first + options_.frames_per_place; ++match) {
        if (IsLoop(query, match)) pairs.emplace_back(query, match);
      }
    }
  }
  return pairs;
}

int PlaceSequence::revisit_frames() const {
  int frames = 0;
  for (const auto& visits : visits_of_place_) {
    if (visits.size() > 1)
      frames += static_cast<int>(visits.size() - 1) * options_.frames_per_place;
  }
  return frames;
}

void PlaceSequence::Write(const std::string& folder, const std::function<void(int)>& written,
                          GeneratedLayout layout) const {
  WriteSequence(
      folder, size(), [this](int index) { return Render(index); }, GroundTruthPairs(), written,
      layout);
}

}  // namespace memloop
