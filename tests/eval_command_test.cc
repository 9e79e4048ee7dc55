// `memloop eval` as a user scores a run: a data set folder, or a CSV of pairs with the pairs to
// ignore beside it, and the run's own operating point named before the swept figure.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_helpers.h"
#include "memloop/run_csv.h"
#include "route_images_test.h"

namespace memloop {
namespace {

class EvalCommandTest : public testing::RouteImagesTest<EvalCommandTest> {
 protected:
  // The route's loop pairs by name, as `memloop generate` writes them.
  static std::vector<std::pair<std::string, std::string>> RoutePairs() {
    std::ifstream in(folder_->File("ground_truth_pairs.csv"));
    std::vector<std::pair<std::string, std::string>> pairs;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      const auto comma = line.find(',');
      pairs.emplace_back(line.substr(0, comma), line.substr(comma + 1));
    }
    return pairs;
  }
};

void WritePairs(const std::string& path,
                const std::vector<std::pair<std::string, std::string>>& pairs) {
  std::ofstream out(path);
  out << "query,match\n";
  for (const auto& [query, match] : pairs) out << query << "," << match << "\n";
}

// Hand-made ground truth: the pairs of the run's first three true loop closures move from the
// loop pairs to the ignored pairs. Scored with the loop pairs alone, those three become false
// positives; with --ignore, or the data set folder that holds both files, they are on ignored
// pairs, neither true nor false, and the run's precision is whole again.
TEST_F(EvalCommandTest, IgnoredPairsBesideThePairsCsvAndTheDatasetFolder) {
  const std::string run = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + run).exit_code, 0);
  const auto pairs = RoutePairs();
  const std::set<std::pair<std::string, std::string>> loop_pairs(pairs.begin(), pairs.end());
  const std::vector<RunRow> rows = ReadRunCsv(run);
  std::set<std::string> moved;  // queries whose pairs become ignored
  int accepted = 0;
  for (const RunRow& row : rows) {
    if (row.matched_images.empty()) continue;
    ++accepted;
    const std::string& match = rows[row.matched_images.front()].name;
    if (moved.size() < 3 && loop_pairs.count({row.name, match})) moved.insert(row.name);
  }
  ASSERT_EQ(moved.size(), 3u);
  std::vector<std::pair<std::string, std::string>> kept, ignored;
  for (const auto& pair : pairs) (moved.count(pair.first) ? ignored : kept).push_back(pair);
  const std::string set = dir_.File("set");
  std::filesystem::create_directories(set);
  WritePairs(set + "/ground_truth_pairs.csv", kept);
  WritePairs(set + "/ground_truth_ignore.csv", ignored);

  const auto accepted_line = [](const Outcome& outcome) {
    const size_t at = outcome.output.find("the run accepted, at its T_loop: ");
    return at == std::string::npos ? ""
                                   : outcome.output.substr(at, outcome.output.find('\n', at) - at);
  };
  const Outcome pairs_only = Memloop("eval " + run + " " + set + "/ground_truth_pairs.csv");
  ASSERT_EQ(pairs_only.exit_code, 0) << pairs_only.output;
  std::ostringstream three_false;
  three_false << "the run accepted, at its T_loop: " << accepted << " loop closures (true "
              << accepted - 3 << ", false 3, on ignored pairs 0)";
  EXPECT_TRUE(Contains(accepted_line(pairs_only), three_false.str())) << pairs_only.output;

  const Outcome with_ignore =
      Memloop("eval " + run + " " + set + "/ground_truth_pairs.csv --ignore " + set +
              "/ground_truth_ignore.csv");
  ASSERT_EQ(with_ignore.exit_code, 0) << with_ignore.output;
  std::ostringstream three_ignored;
  three_ignored << "the run accepted, at its T_loop: " << accepted << " loop closures (true "
                << accepted - 3 << ", false 0, on ignored pairs 3): precision 100.0%";
  EXPECT_TRUE(Contains(accepted_line(with_ignore), three_ignored.str())) << with_ignore.output;
  EXPECT_TRUE(Contains(with_ignore.output, "(ignored pairs: " + set + "/ground_truth_ignore.csv)"))
      << with_ignore.output;
  // The run's own figure comes before the one a threshold chosen afterwards gives.
  EXPECT_LT(with_ignore.output.find("the run accepted"), with_ignore.output.find("best threshold"));

  const Outcome folder = Memloop("eval " + run + " " + set);
  ASSERT_EQ(folder.exit_code, 0) << folder.output;
  EXPECT_EQ(accepted_line(folder), accepted_line(with_ignore));
  const Outcome json = Memloop("eval " + run + " " + set + " --json");
  EXPECT_TRUE(Contains(json.output, "ground_truth_ignore.csv")) << json.output;
  EXPECT_TRUE(Contains(json.output, "\"ignored\": 3")) << json.output;

  // The report reads the same folder.
  const Outcome report = Memloop("report " + run + " " + set + " --out " + dir_.File("r.html"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_TRUE(Contains(ReadFile(dir_.File("r.html")), "ground_truth_ignore.csv"));
}

// Bad input: a folder without ground truth, an --ignore that names an unknown image, a --format
// with a folder, a --map that is not a map, --ignore without ground truth: one line each, a
// nonzero exit.
TEST_F(EvalCommandTest, BadGroundTruthArgumentsAreRefusedWithOneLine) {
  const std::string run = dir_.File("run.csv");
  ASSERT_EQ(Memloop("run " + Images() + " --set memory.time_limit_ms=0 --out " + run).exit_code, 0);
  const std::string empty = dir_.File("empty");
  std::filesystem::create_directories(empty);
  const Outcome no_truth = Memloop("eval " + run + " " + empty);
  EXPECT_NE(no_truth.exit_code, 0);
  EXPECT_TRUE(
      Contains(no_truth.output, "memloop: error: " + empty + ": no ground truth in this folder"))
      << no_truth.output;
  std::ofstream(dir_.File("ignore.csv")) << "query,match\nnot_an_image.png,1.png\n";
  const Outcome unknown = Memloop("eval " + run + " " + folder_->File("ground_truth_pairs.csv") +
                                  " --ignore " + dir_.File("ignore.csv"));
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_TRUE(Contains(
      unknown.output, dir_.File("ignore.csv") + ": line 2: 'not_an_image.png' is neither an image"))
      << unknown.output;
  const Outcome format =
      Memloop("eval " + run + " " + folder_->path().string() + " --format image");
  EXPECT_NE(format.exit_code, 0);
  EXPECT_TRUE(Contains(format.output, "a data set folder picks its own ground truth"))
      << format.output;
  std::ofstream(dir_.File("not_a_map.db")) << "not a map";
  const Outcome not_a_map = Memloop("eval " + run + " " + folder_->path().string() + " --map " +
                                    dir_.File("not_a_map.db"));
  EXPECT_NE(not_a_map.exit_code, 0);
  EXPECT_TRUE(Contains(not_a_map.output, "memloop: error: " + dir_.File("not_a_map.db")))
      << not_a_map.output;
  const Outcome report = Memloop("report " + run + " --ignore " + dir_.File("ignore.csv") +
                                 " --out " + dir_.File("r.html"));
  EXPECT_NE(report.exit_code, 0);
  EXPECT_TRUE(Contains(report.output, "--ignore: needs the ground truth")) << report.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("r.html")));
}

}  // namespace
}  // namespace memloop
