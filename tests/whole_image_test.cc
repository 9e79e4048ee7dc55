// The whole-image channel (features.whole_image, `--preset day-night`) as part of memory
// management: each location's descriptor goes to LTM with it, comes back on retrieval, is in the
// resume checkpoint, and a resumed run goes on as if never stopped.
#include <gtest/gtest.h>

#include "memloop/detector.h"
#include "memloop/map_info.h"
#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop {
namespace {

// The channel under a small WM (transfers and retrievals); T_time off. The agreement over
// images is not in the checkpoint (whole_image_agreement.h), so it is off here: every other
// part of the channel's state is.
Options ChannelUnderBudget() {
  Options options = Options::DayNight();
  options.memory.time_limit_ms = 0;
  options.memory.max_wm_locations = 20;
  options.filter.whole_image_agreement = 0;
  return options;
}

std::vector<Result> Process(Detector& detector, const SyntheticRoute& route, int begin, int end) {
  std::vector<Result> results;
  for (int index = begin; index < end; ++index) {
    results.push_back(detector.Process(route.Render(index), index));
    for (const std::string& problem : detector.CheckConsistency()) {
      ADD_FAILURE() << "after image " << index << ": " << problem;
    }
  }
  return results;
}

TEST(WholeImageTest, DescriptorsGoToLtmComeBackAndResume) {
  const SyntheticRoute route(testing::ShortRoute());
  testing::TempDir dir;
  std::vector<Result> whole;
  {
    Detector detector(ChannelUnderBudget(), dir.File("whole.db"));
    whole = Process(detector, route, 0, route.size());
  }
  int retrieved = 0;
  for (const Result& result : whole) retrieved += static_cast<int>(result.retrieved_ids.size());
  EXPECT_GT(retrieved, 0);  // locations came back from LTM, their descriptors with them
  // After Close every location is in LTM, each with its descriptor.
  const MapInfo info = InspectMap(dir.File("whole.db"));
  EXPECT_GT(info.locations, 0);
  EXPECT_EQ(info.whole_images, info.locations);

  // Stopped half way and resumed: the same results, image for image (a descriptor lost in the
  // checkpoint or in LTM would change the channel's scores, then the filter).
  const int half = route.size() / 2;
  {
    Detector first(ChannelUnderBudget(), dir.File("resumed.db"));
    Process(first, route, 0, half);
  }
  Detector resumed(ChannelUnderBudget(), dir.File("resumed.db"), MapMode::kResume);
  const std::vector<Result> rest = Process(resumed, route, half, route.size());
  ASSERT_EQ(rest.size(), whole.size() - half);
  for (size_t i = 0; i < rest.size(); ++i) {
    const Result& a = whole[half + i];
    const Result& b = rest[i];
    ASSERT_EQ(a.hypothesis_id, b.hypothesis_id) << "image " << a.image_index;
    ASSERT_EQ(a.hypothesis_value, b.hypothesis_value) << "image " << a.image_index;
    ASSERT_EQ(a.loop_closure_id, b.loop_closure_id) << "image " << a.image_index;
    ASSERT_EQ(a.retrieved_ids, b.retrieved_ids) << "image " << a.image_index;
  }
}

// The map defines whether locations have descriptors: resuming with the channel switched is
// refused, naming the parameter.
TEST(WholeImageTest, ResumingWithTheChannelSwitchedIsRefused) {
  const SyntheticRoute route(testing::ShortRoute());
  testing::TempDir dir;
  {
    Detector detector(ChannelUnderBudget(), dir.File("map.db"));
    Process(detector, route, 0, 30);
  }
  Options words = ChannelUnderBudget();
  words.features.whole_image = 0;
  try {
    Detector resumed(words, dir.File("map.db"), MapMode::kResume);
    ADD_FAILURE() << "resumed with features.whole_image switched off";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("features.whole_image"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace memloop
