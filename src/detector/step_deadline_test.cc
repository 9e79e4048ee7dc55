#include "detector/step_deadline.h"

#include <gtest/gtest.h>

#include <cmath>

namespace memloop {
namespace {

TEST(StepDeadlineTest, ExpectedCostIsTheMeanPlusTwiceTheDeviation) {
  StepCost cost;
  EXPECT_FALSE(cost.measured());
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 0);
  cost.Record(10);  // mean 10, deviation 10 / 2
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 20);
  cost.Record(20);  // deviation 5 + (10 - 5) / 4 = 6.25, mean 10 + 10 / 8 = 11.25
  EXPECT_DOUBLE_EQ(cost.deviation_ms(), 6.25);
  EXPECT_DOUBLE_EQ(cost.mean_ms(), 11.25);
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 23.75);
  cost.Record(2);  // deviation 6.25 + (9.25 - 6.25) / 4 = 7, mean 11.25 - 9.25 / 8 = 10.09375
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 24.09375);
}

TEST(StepDeadlineTest, AStepFitsWhenItsExpectedTimeEndsBeforeTheDeadline) {
  StepCost cost;
  cost.Record(8);  // expected 8 + 2 x 4 = 16
  const auto at = [](double ms) { return [ms] { return ms; }; };
  EXPECT_TRUE(StepDeadline(at(20), 40, &cost).Fits());   // 20 + 16 <= 40
  EXPECT_TRUE(StepDeadline(at(24), 40, &cost).Fits());   // 40, just
  EXPECT_FALSE(StepDeadline(at(25), 40, &cost).Fits());  // 41
  EXPECT_TRUE(StepDeadline(at(1000), 0, &cost).Fits());  // no deadline (T_time off)
  EXPECT_TRUE(StepDeadline().Fits());
  StepCost unmeasured;
  EXPECT_TRUE(StepDeadline(at(39), 40, &unmeasured).Fits());
  EXPECT_FALSE(StepDeadline(at(41), 40, &unmeasured).Fits());  // already past it
}

TEST(StepDeadlineTest, SlackIsWhatIsLeftAfterTheExpectedTime) {
  StepCost cost;
  cost.Record(8);  // expected 16
  const auto at = [](double ms) { return [ms] { return ms; }; };
  EXPECT_DOUBLE_EQ(StepDeadline(at(20), 40, &cost).SlackMs(), 4);  // 40 - 20 - 16
  EXPECT_DOUBLE_EQ(StepDeadline(at(30), 40, &cost).SlackMs(), 0);  // late: none, not -6
  EXPECT_DOUBLE_EQ(StepDeadline(at(20), 40, nullptr).SlackMs(), 20);
  EXPECT_TRUE(std::isinf(StepDeadline(at(20), 0, &cost).SlackMs()));  // no deadline
  EXPECT_TRUE(std::isinf(StepDeadline().SlackMs()));
}

TEST(StepDeadlineTest, DeferralsShrinkTheBoundAndEndInAProbe) {
  StepCost cost;
  cost.Record(8);
  cost.Record(48);  // one slow step: deviation 4 + (40 - 4) / 4 = 13, mean 13
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 39);
  const auto at = [](double ms) { return [ms] { return ms; }; };
  EXPECT_FALSE(StepDeadline(at(15), 47, &cost).Fits());  // 15 + 39 > 47
  cost.Deferred();  // deviation 13 x 3/4 = 9.75: 13 + 19.5 = 32.5
  EXPECT_DOUBLE_EQ(cost.expected_ms(), 32.5);
  EXPECT_FALSE(StepDeadline(at(15), 47, &cost).Fits());
  cost.Deferred();  // deviation 7.3125: 27.625
  EXPECT_TRUE(StepDeadline(at(15), 47, &cost).Fits());
  // A mean that stays high (slow steps in a row) is probed after kProbeAfter deferrals.
  StepCost slow;
  slow.Record(40);
  for (int k = 1; k < StepCost::kProbeAfter; ++k) slow.Deferred();
  EXPECT_FALSE(StepDeadline(at(15), 47, &slow).Fits());
  slow.Deferred();
  EXPECT_TRUE(slow.probe_due());
  EXPECT_TRUE(StepDeadline(at(15), 47, &slow).Fits());   // the probe
  EXPECT_FALSE(StepDeadline(at(48), 47, &slow).Fits());  // not past the deadline
  slow.Record(10);
  EXPECT_FALSE(slow.probe_due());
}

}  // namespace
}  // namespace memloop
