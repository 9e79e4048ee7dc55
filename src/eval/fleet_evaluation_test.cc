#include "memloop/fleet_evaluation.h"

#include <gtest/gtest.h>

#include <fstream>

#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

RunRow Row(ImageIndex image, const std::string& name, const std::string& matched_robot = "",
           std::vector<ImageIndex> matched = {}) {
  RunRow row;
  row.image = image;
  row.name = name;
  row.matched_robot = matched_robot;
  row.matched_images = std::move(matched);
  return row;
}

TEST(ReadFleetPairs, ReadsBothWays) {
  testing::TempDir dir;
  std::ofstream(dir.File("pairs.csv")) << "robot,image,other,other_image\n"
                                          "a,1.png,b,7.png\n\"a\",2.png,b,8.png\n";
  const FleetTruth truth = ReadFleetPairs(dir.File("pairs.csv"));
  ASSERT_EQ(truth.size(), 4u);
  EXPECT_EQ(truth.at({"b", "7.png"}),
            (std::set<std::pair<std::string, std::string>>{{"a", "1.png"}}));
  EXPECT_EQ(truth.at({"a", "2.png"}),
            (std::set<std::pair<std::string, std::string>>{{"b", "8.png"}}));
}

TEST(ReadFleetPairs, RefusesAMalformedFile) {
  testing::TempDir dir;
  const auto refused = [&](const std::string& text, const std::string& problem) {
    std::ofstream(dir.File("pairs.csv")) << text;
    try {
      ReadFleetPairs(dir.File("pairs.csv"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(problem), std::string::npos) << error.what();
    }
  };
  refused("", "not a fleet's pairs");
  refused("robot,image,other,other_image\na,1.png,,2.png\n", "line 2: a field is empty");
  refused("robot,image,other,other_image\na,1.png,b,2.png,x\n", "line 2: has 5 fields, not 4");
  refused("robot,image,other,other_image\nb,1.png,b,2.png\n", "line 2: pairs robot b with itself");
  EXPECT_THROW(ReadFleetPairs(dir.File("missing.csv")), InputError);
}

// Robot b saw a's places at its images 1-3 (names 11-13.png, a's 1-3.png); it closed a loop
// with a at 1 (right: a's image 0 is 1.png), at 2 (wrong: a's 2 is 3.png), and with its own
// place at 3, which is not this evaluation's.
TEST(EvaluateFleet, JudgesLoopClosuresWithOtherRobotsPlaces) {
  FleetTruth truth;
  for (int k = 1; k <= 3; ++k) {
    const std::string a = std::to_string(k) + ".png", b = std::to_string(10 + k) + ".png";
    truth[{"a", a}].insert({"b", b});
    truth[{"b", b}].insert({"a", a});
  }
  const std::vector<FleetRun> runs = {{"a", {Row(0, "1.png"), Row(1, "2.png"), Row(2, "3.png")}},
                                      {"b",
                                       {Row(0, "10.png"), Row(1, "11.png", "a", {0}),
                                        Row(2, "12.png", "a", {2}), Row(3, "13.png", "", {1})}}};
  const FleetEvaluation e = EvaluateFleet(runs, {truth, {}});
  ASSERT_EQ(e.robots.size(), 2u);
  const FleetRobotEvaluation& a = e.robots[0];
  EXPECT_EQ(a.images, 3);
  EXPECT_EQ(a.shared_images, 3);
  EXPECT_EQ(a.detections, 0);
  const FleetRobotEvaluation& b = e.robots[1];
  EXPECT_EQ(b.images, 4);
  EXPECT_EQ(b.shared_images, 3);
  EXPECT_EQ(b.detections, 2);
  EXPECT_EQ(b.true_positives, 1);
  EXPECT_EQ(b.false_positives, 1);
  EXPECT_EQ(b.found_images, 1);
  EXPECT_EQ(e.total.images, 7);
  EXPECT_EQ(e.total.shared_images, 6);
  EXPECT_EQ(e.total.false_positives, 1);
}

// The same, a's image 3.png on b's 12.png's ignored band: its detection counts for neither.
TEST(EvaluateFleet, ADetectionOnTheIgnoredBandCountsForNeither) {
  FleetGroundTruth truth;
  truth.same_place[{"b", "11.png"}].insert({"a", "1.png"});
  truth.same_place[{"b", "12.png"}].insert({"a", "2.png"});
  truth.ignored[{"b", "12.png"}].insert({"a", "3.png"});
  const std::vector<FleetRun> runs = {
      {"a", {Row(0, "1.png"), Row(1, "2.png"), Row(2, "3.png")}},
      {"b", {Row(1, "11.png", "a", {0}), Row(2, "12.png", "a", {2})}}};
  const FleetRobotEvaluation b = EvaluateFleet(runs, truth).robots[1];
  EXPECT_EQ(b.detections, 1);
  EXPECT_EQ(b.true_positives, 1);
  EXPECT_EQ(b.false_positives, 0);
  EXPECT_EQ(b.ignored, 1);
  EXPECT_EQ(b.found_images, 1);
}

TEST(EvaluateFleet, NeedsTheRunOfEveryRobotItNames) {
  const std::vector<FleetRun> runs = {{"b", {Row(0, "1.png", "a", {0})}}};
  EXPECT_THROW(EvaluateFleet(runs, {}), InputError);
  const std::vector<FleetRun> beyond = {{"a", {Row(0, "1.png")}},
                                        {"b", {Row(0, "1.png", "a", {5})}}};
  EXPECT_THROW(EvaluateFleet(beyond, {}), InputError);
}

}  // namespace
}  // namespace memloop
