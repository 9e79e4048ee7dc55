// The whole-image channel (`--preset day-night`, issue 34) on a generated route whose second lap
// and everything after are seen "at night": blurred, darker, another gamma and contrast, sensor
// noise and a few bright spots (street lights). The route's street front (facades of their own
// gray and height) is the large-scale structure a change of light leaves; the small shapes SURF
// describes by day are gone. Ground truth is the route's, exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "features/whole_image_descriptor.h"
#include "memloop/synthetic_route.h"
#include "route_frames_run.h"

namespace memloop {
namespace {

SyntheticRouteOptions Route() {
  SyntheticRouteOptions options;
  options.lap_frames = 40;
  options.detour_frames = 10;
  options.third_lap_frames = 10;
  options.facades = true;
  return options;
}

// The first lap and the first detour by day, the rest by night.
constexpr int kNightFrom = 50;

cv::Mat Night(const cv::Mat& day, int index) {
  cv::Mat value;
  day.convertTo(value, CV_32F, 1.0 / 255);
  cv::GaussianBlur(value, value, cv::Size(), 4);  // long exposure, out of focus
  cv::pow(value, 2.2, value);
  value *= 0.3;
  cv::RNG rng(static_cast<uint64_t>(index) * 7919u + 1);
  for (int n = 0; n < 3; ++n) {
    cv::Mat glow = cv::Mat::zeros(day.size(), CV_32FC3);
    const cv::Point centre(rng.uniform(0, day.cols), rng.uniform(0, day.rows / 2));
    cv::circle(glow, centre, rng.uniform(3, 7), cv::Scalar::all(1.0), cv::FILLED, cv::LINE_AA);
    cv::GaussianBlur(glow, glow, cv::Size(), 4);
    value += glow * 2;
  }
  cv::Mat noise(day.size(), CV_32FC3);
  rng.fill(noise, cv::RNG::NORMAL, 0, 0.05);
  value += noise;
  cv::Mat night;
  value.convertTo(night, CV_8U, 255);
  return night;
}

// Another change of conditions than light, which the channel was not tuned on: snow. Brighter
// and flatter, a cold colour cast, and the ground (the image's lower third) under a white cover
// of its own texture: a whole-image description sees a new ground and the same skyline.
cv::Mat Snow(const cv::Mat& day, int index) {
  cv::Mat value;
  day.convertTo(value, CV_32F, 1.0 / 255);
  value = 0.45 + 0.55 * value;
  cv::multiply(value, cv::Scalar(1.05, 0.97, 0.9), value);  // BGR: bluish
  const int ground = day.rows * 2 / 3;
  cv::Mat cover(day.rows - ground, day.cols, CV_32FC1);
  cv::RNG rng(static_cast<uint64_t>(index) * 104729u + 3);
  rng.fill(cover, cv::RNG::NORMAL, 0.92, 0.05);
  cv::GaussianBlur(cover, cover, cv::Size(), 1.5);
  cv::Mat cover3;
  cv::cvtColor(cover, cover3, cv::COLOR_GRAY2BGR);
  cover3.copyTo(value.rowRange(ground, day.rows));
  cv::Mat snow;
  value.convertTo(snow, CV_8U, 255);
  return snow;
}

enum class Change { kNight, kSnow };  // what the frames from kNightFrom on are seen under

cv::Mat Frame(const SyntheticRoute& route, int index, Change change = Change::kNight) {
  const cv::Mat image = route.Render(index);
  if (index < kNightFrom) return image;
  return change == Change::kSnow ? Snow(image, index) : Night(image, index);
}

bool RevisitsTheDay(const SyntheticRoute& route, int index) {
  for (int match = 0; match < kNightFrom; ++match) {
    if (route.IsLoop(index, match)) return true;
  }
  return false;
}

// The descriptor alone: each night image against every earlier image but its last 10 (its own
// stretch of the night), the best by WholeImageSimilarity is its day place.
TEST(DayNightRouteTest, TheDescriptorFindsTheDayPlaceOfNightImages) {
  const SyntheticRoute route(Route());
  std::vector<WholeImageDescriptor> descriptors;
  for (int index = 0; index < route.size(); ++index) {
    cv::Mat gray;
    cv::cvtColor(Frame(route, index), gray, cv::COLOR_BGR2GRAY);
    descriptors.push_back(DescribeWholeImage(gray));
  }
  int revisits = 0, found = 0;
  for (int query = kNightFrom; query < route.size(); ++query) {
    if (!RevisitsTheDay(route, query)) continue;
    ++revisits;
    int best = 0;
    for (int other = 1; other < query - 10; ++other) {
      if (WholeImageSimilarity(descriptors[query], descriptors[other]) >
          WholeImageSimilarity(descriptors[query], descriptors[best])) {
        best = other;
      }
    }
    found += route.IsLoop(query, best) ? 1 : 0;
  }
  ASSERT_EQ(revisits, 50);
  EXPECT_GE(found, 45) << "of 50 night images, the best is the day place";  // measured 49
}

struct RouteRun {
  PrecisionRecall score;
  std::vector<std::pair<ImageIndex, std::vector<ImageIndex>>> loop_closures;  // query, matches
  int night_found = 0;  // night images closed on their day place
};

// `night_session`: the night is a new session of the day's map, as a robot maps it.
RouteRun RunNightRoute(const Options& options, bool night_session, Change change = Change::kNight) {
  const SyntheticRoute route(Route());
  const testing::FramesRun frames = testing::RunFrames(
      options, route.size(), [&](int index) { return Frame(route, index, change); },
      night_session ? kNightFrom : -1);
  RouteRun run;
  for (const Result& result : frames.loop_closures) {
    run.loop_closures.emplace_back(result.image_index, result.loop_closure_images);
    const int index = static_cast<int>(result.image_index);
    const bool found = std::any_of(result.loop_closure_images.begin(),
                                   result.loop_closure_images.end(), [&](ImageIndex match) {
                                     return static_cast<int>(match) < kNightFrom &&
                                            route.IsLoop(index, static_cast<int>(match));
                                   });
    run.night_found += index >= kNightFrom && found ? 1 : 0;
  }
  run.score = Evaluate(frames.detections, route.Truth());
  return run;
}

// The night mapped as a new session of the day's map: the words alone find one of the night
// images' day places; the channel, with its agreement over images, finds several, and neither
// makes a false loop closure.
TEST(DayNightRouteTest, TheChannelFindsNightRevisitsThatWordsMiss) {
  const RouteRun words = RunNightRoute(Options(), true);
  const RouteRun channel = RunNightRoute(Options::DayNight(), true);
  std::cout << "night images closed on their day place, of 50: words " << words.night_found
            << ", with the whole-image channel " << channel.night_found << "\n";
  EXPECT_EQ(words.score.false_positives, 0);
  EXPECT_EQ(channel.score.false_positives, 0);
  EXPECT_LE(words.night_found, 1);    // measured 1
  EXPECT_GE(channel.night_found, 6);  // measured 9 (in one session, with every location: 2)
}

// Within one session the light is the same and the words judge (filter.whole_image_scope): the
// preset's loop closures are the defaults', image for image. Weighing every location instead
// ("all") lets the channel act within the session.
TEST(DayNightRouteTest, WithinOneSessionTheChannelStaysOut) {
  const RouteRun words = RunNightRoute(Options(), false);
  const RouteRun channel = RunNightRoute(Options::DayNight(), false);
  EXPECT_FALSE(words.loop_closures.empty());
  EXPECT_EQ(channel.loop_closures, words.loop_closures);
  EXPECT_EQ(channel.night_found, 0);
  Options all = Options::DayNight();
  all.filter.whole_image_scope = "all";
  const RouteRun all_run = RunNightRoute(all, false);
  std::cout << "in one session, night images closed on their day place by the channel weighing "
               "every location: "
            << all_run.night_found << "\n";
  EXPECT_GE(all_run.night_found, 1);  // measured 3
}

// A change the channel was not tuned on: the laps after the first detour under snow, as a new
// session. `--preset day-night` makes no false loop closure (measured: 35 of 50 snow images
// closed on their day place). The words alone (the defaults) find 45 but close one snow image
// (90) on the first lap's end (37), a false positive whose cause is still to be found.
TEST(DayNightRouteTest, SnowIsAnotherChangeWithoutFalseLoopClosures) {
  const RouteRun words = RunNightRoute(Options(), true, Change::kSnow);
  const RouteRun channel = RunNightRoute(Options::DayNight(), true, Change::kSnow);
  std::cout << "snow images closed on their day place, of 50: words " << words.night_found
            << " (false " << words.score.false_positives << "), with the whole-image channel "
            << channel.night_found << " (false " << channel.score.false_positives << ")\n";
  EXPECT_EQ(channel.score.false_positives, 0);
  EXPECT_GE(channel.night_found, 20);  // measured 35
}

}  // namespace
}  // namespace memloop
