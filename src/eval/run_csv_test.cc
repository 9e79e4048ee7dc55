#include "memloop/run_csv.h"

#include <gtest/gtest.h>

#include <fstream>

#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

TEST(RunCsvTest, WrittenRowsReadBack) {
  testing::TempDir dir;
  const std::string path = dir.File("run.csv");
  Result first;
  first.image_index = 0;
  first.location_id = 1;
  first.hypothesis_id = kNoLocation;
  first.times.total_ms = 12.5;
  first.times.cpu_ms = 5.25;
  Result second;
  second.image_index = 3;
  second.location_id = 4;
  second.loop_closure_id = 1;
  second.loop_closure_images = {0, 1};
  second.hypothesis_id = 1;
  second.hypothesis_value = 0.375;
  second.hypothesis_images = {0, 1};
  second.wm_size = 17;
  second.ltm_size = 4321;
  second.dictionary_size = 900;
  {
    RunCsvWriter writer(path);
    writer.Write("a, \"quoted\".png", first);
    writer.Write("d.png", second);
  }
  const std::vector<RunRow> rows = ReadRunCsv(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].name, "a, \"quoted\".png");
  EXPECT_TRUE(rows[0].matched_images.empty());
  EXPECT_EQ(rows[0].iteration_ms, 12.5);
  EXPECT_EQ(rows[0].cpu_ms, 5.25);
  EXPECT_EQ(rows[1].image, 3);
  EXPECT_EQ(rows[1].matched_images, (std::vector<ImageIndex>{0, 1}));
  EXPECT_EQ(rows[1].hypothesis_value, 0.375);
  EXPECT_EQ(rows[1].hypothesis_images, (std::vector<ImageIndex>{0, 1}));
  EXPECT_EQ(rows[1].wm_size, 17);
  EXPECT_EQ(rows[1].ltm_size, 4321);
  EXPECT_EQ(rows[1].dictionary_size, 900);
}

TEST(RunCsvTest, NotARunOrMalformedIsRefused) {
  testing::TempDir dir;
  const auto expect_error = [&](const std::string& text, const std::string& reason) {
    std::ofstream(dir.File("bad.csv")) << text;
    try {
      ReadRunCsv(dir.File("bad.csv"));
      FAIL() << text;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
  };
  expect_error("", "is empty");
  expect_error("query,match\n1,2\n", "not a memloop run CSV (no column 'image')");
  RunCsvWriter(dir.File("good.csv")).Write("x.png", Result());
  std::ifstream good(dir.File("good.csv"));
  std::string header;
  std::getline(good, header);
  expect_error(header + "\n", "holds no image row");
  expect_error(header + "\n1,2\n", "line 2 has 2 fields");
  std::string row(std::count(header.begin(), header.end(), ','), ',');
  expect_error(header + "\nseven" + row + "\n", "line 2: image 'seven' is not a whole number");
  EXPECT_THROW(ReadRunCsv(dir.File("absent.csv")), InputError);
}

}  // namespace
}  // namespace memloop
