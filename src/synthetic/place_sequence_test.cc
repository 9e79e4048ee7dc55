#include "memloop/place_sequence.h"

#include <gtest/gtest.h>

#include "memloop/errors.h"

namespace memloop {
namespace {

// 4 places of 3 frames, a revisit after every 2 new places, no minimum age: place 0, place 1,
// a revisit of place 0 (the only earlier one), place 2, place 3, a revisit of one of 0-2.
PlaceSequenceOptions Small() {
  PlaceSequenceOptions options;
  options.places = 4;
  options.frames_per_place = 3;
  options.revisit_every = 2;
  options.min_revisit_age = 0;
  options.image_width = 64;
  options.image_height = 48;
  options.step_px = 32;  // views 32 px apart; same place within 0.6 x 64 = 38.4 px (jitter 12)
  return options;
}

TEST(PlaceSequenceTest, ScheduleAndGroundTruthByHand) {
  const PlaceSequence sequence(Small());
  EXPECT_EQ(sequence.size(), 4 * 3 + 2 * 3);
  EXPECT_EQ(sequence.revisits(), 2);
  EXPECT_EQ(sequence.revisit_frames(), 6);
  // Frames 6-8 revisit place 0 (frames 0-2): offsets 0, 1, 2.
  EXPECT_FALSE(sequence.IsLoop(1, 0));  // the same visit: neighbours
  EXPECT_FALSE(sequence.IsLoop(3, 0));  // another place
  EXPECT_FALSE(sequence.IsLoop(0, 6));  // the match must come first
  // |0 x 32 + dx - 2 x 32 - dx'| >= 64 - 24 = 40 > 38.4: two steps apart is not the same place.
  EXPECT_FALSE(sequence.IsLoop(6, 2));
  int pairs_with_revisit = 0;
  for (const auto& [query, match] : sequence.GroundTruthPairs()) {
    EXPECT_GT(query, match);
    EXPECT_TRUE(sequence.IsLoop(query, match));
    pairs_with_revisit += query >= 6 && query <= 8;
  }
  EXPECT_TRUE(sequence.IsLoop(6, 0));  // same offset: within the jitter
  EXPECT_TRUE(sequence.IsLoop(7, 1));
  EXPECT_GE(pairs_with_revisit, 3);
}

TEST(PlaceSequenceTest, OldPlacesOnlyAndRepeatableImages) {
  PlaceSequenceOptions options = Small();
  options.min_revisit_age = 1000;  // no place is ever that old here
  const PlaceSequence no_revisit(options);
  EXPECT_EQ(no_revisit.revisits(), 0);
  EXPECT_EQ(no_revisit.size(), 12);
  EXPECT_TRUE(no_revisit.GroundTruthPairs().empty());

  const PlaceSequence a(Small());
  const PlaceSequence b(Small());
  const cv::Mat frame = a.Render(7);
  EXPECT_EQ(frame.type(), CV_8UC3);
  EXPECT_EQ(frame.cols, 64);
  EXPECT_EQ(frame.rows, 48);
  EXPECT_EQ(cv::norm(frame, b.Render(7), cv::NORM_L1), 0.0);  // same seed, same image
  a.Render(0);  // out of order: the texture cache is rebuilt
  EXPECT_EQ(cv::norm(frame, a.Render(7), cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(a.Render(0), a.Render(3), cv::NORM_L1), 0.0);  // two places differ
}

TEST(PlaceSequenceTest, InvalidOptionsAreRefused) {
  PlaceSequenceOptions options = Small();
  options.places = 0;
  EXPECT_THROW(PlaceSequence{options}, InputError);
  options = Small();
  options.frames_per_place = 0;
  EXPECT_THROW(PlaceSequence{options}, InputError);
  options = Small();
  options.revisit_every = -1;
  EXPECT_THROW(PlaceSequence{options}, InputError);
}

}  // namespace
}  // namespace memloop
