#include "detector/session_numbering.h"

#include <gtest/gtest.h>

#include "memloop/errors.h"

namespace memloop {
namespace {

MapSession Session(int id, ImageIndex first, ImageIndex last) {
  MapSession session;
  session.id = id;
  session.first_image = first;
  session.last_image = last;
  return session;
}

TEST(SessionNumberingTest, ANewMapIsSessionZeroFromItsFirstImage) {
  SessionNumbering sessions;
  EXPECT_EQ(sessions.id(), 0);
  EXPECT_EQ(sessions.first_image(0), 0);  // none yet: the next image
  sessions.CheckImage(5);                 // no earlier session: any index
  sessions.Record(5);
  sessions.Record(6);
  EXPECT_EQ(sessions.first_image(7), 5);
}

TEST(SessionNumberingTest, ANewSessionsImagesComeAfterTheEarlierOnes) {
  SessionNumbering sessions;
  sessions.Record(0);
  sessions.StartNew(/*last_image=*/49);
  EXPECT_EQ(sessions.id(), 1);
  EXPECT_EQ(sessions.first_image(50), 50);
  EXPECT_THROW(sessions.CheckImage(49), InputError);
  EXPECT_THROW(sessions.CheckImage(0), InputError);
  sessions.CheckImage(kNoImage);  // numbered by the detector, after the last
  sessions.CheckImage(50);
  sessions.Record(60);
  EXPECT_EQ(sessions.first_image(61), 60);
}

TEST(SessionNumberingTest, AResumedMapGoesOnInItsLastSession) {
  SessionNumbering sessions;
  sessions.Resume({Session(0, 3, 49), Session(1, 50, 99)}, 99);
  EXPECT_EQ(sessions.id(), 1);
  EXPECT_EQ(sessions.first_image(100), 50);
  EXPECT_THROW(sessions.CheckImage(49), InputError);
  sessions.CheckImage(50);  // the last session's own images may be given again by index

  // The first session starts at image 0 whatever it recorded (images recorded from an upgrade).
  sessions.Resume({Session(0, 30, 49)}, 49);
  EXPECT_EQ(sessions.id(), 0);
  EXPECT_EQ(sessions.first_image(50), 0);
  sessions.CheckImage(0);

  // No session recorded (a map made before images were): session 0 from image 0, or none yet.
  sessions.Resume({}, 20);
  EXPECT_EQ(sessions.first_image(21), 0);
  sessions.Resume({Session(0, 0, 9), Session(1, 10, 19)}, 19);
  sessions.Resume({}, kNoImage);
  EXPECT_EQ(sessions.id(), 0);
  EXPECT_EQ(sessions.first_image(7), 7);
  sessions.CheckImage(0);  // nothing earlier any more
}

}  // namespace
}  // namespace memloop
