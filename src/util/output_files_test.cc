#include "util/output_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "memloop/errors.h"
#include "temp_dir.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// The refusal's message, "" when the outputs are accepted.
std::string Refusal(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs) {
  try {
    CheckOutputsAreNotInputs(inputs, outputs);
    return "";
  } catch (const InputError& error) {
    return error.what();
  }
}

class OutputFilesTest : public ::testing::Test {
 protected:
  OutputFilesTest() {
    fs::create_directories(dir_.File("data/sub"));
    std::ofstream(dir_.File("data/1.png")) << "image";
    std::ofstream(dir_.File("map.db")) << "map";
  }
  testing::TempDir dir_;
};

TEST_F(OutputFilesTest, AnOutputSpelledAnyWayAsAnInputIsRefusedNamingBoth) {
  const std::vector<NamedPath> map = {{"the map", dir_.File("map.db")}};
  fs::create_symlink(dir_.File("map.db"), dir_.File("link.db"));
  fs::create_hard_link(dir_.File("map.db"), dir_.File("hard.db"));
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_.path());
  for (const std::string& spelling :
       {dir_.File("map.db"), std::string("map.db"), std::string("./map.db"),
        std::string("data/../map.db"), std::string("link.db"), std::string("hard.db")}) {
    const std::string named =
        spelling == dir_.File("map.db") ? "" : " (" + dir_.File("map.db") + ")";
    EXPECT_EQ(Refusal(map, {{"--out", spelling}}),
              spelling + ": is also the map" + named +
                  ": give --out another file (it would be overwritten)")
        << spelling;
  }
  EXPECT_EQ(Refusal(map, {{"--out", "other.json"}}), "");
  EXPECT_EQ(Refusal(map, {{"--out", "data/map.db"}}), "");
  fs::current_path(cwd);
}

TEST_F(OutputFilesTest, TwoOutputsThatWouldBeOneFileAreRefusedExistingOrNot) {
  const std::string csv = dir_.File("new.csv");
  EXPECT_NE(Refusal({}, {{"the map (--db)", csv}, {"--out", dir_.File("data/../new.csv")}}), "");
  // A dangling symlink is where its target would be created.
  fs::create_symlink(dir_.File("target.csv"), dir_.File("dangling.csv"));
  EXPECT_EQ(Refusal({}, {{"the map (--db)", dir_.File("target.csv")},
                         {"--out", dir_.File("dangling.csv")}}),
            dir_.File("dangling.csv") + ": is also the map (--db) (" + dir_.File("target.csv") +
                "): give --out another file (it would be overwritten)");
  EXPECT_EQ(Refusal({}, {{"the map (--db)", dir_.File("a.db")}, {"--out", dir_.File("b.csv")}}),
            "");
}

TEST_F(OutputFilesTest, AFolderWhoseEveryFileIsReadTakesNoOutput) {
  const std::vector<NamedPath> folder = {{"the input folder", dir_.File("data"), true}};
  EXPECT_NE(Refusal(folder, {{"--out", dir_.File("data/1.png")}}).find("is in the input folder"),
            std::string::npos);
  EXPECT_NE(Refusal(folder, {{"--out", dir_.File("data/new.csv")}}), "");
  // A hard link elsewhere to one of its files.
  fs::create_hard_link(dir_.File("data/1.png"), dir_.File("alias.png"));
  EXPECT_NE(Refusal(folder, {{"--out", dir_.File("alias.png")}}), "");
  // Its subfolders are not read.
  EXPECT_EQ(Refusal(folder, {{"--out", dir_.File("data/sub/run.csv")}}), "");
  // A listed input (not every file read): only the file itself.
  EXPECT_EQ(Refusal({{"the input folder", dir_.File("data"), false}},
                    {{"--out", dir_.File("data/new.csv")}}),
            "");
}

TEST_F(OutputFilesTest, AWholeFileReplacesTheOldOneOrLeavesItAndNothingElse) {
  const std::string path = dir_.File("out.json");
  std::ofstream(path) << "old";
  WriteWholeFile(path, "the export file", std::string("new"));
  EXPECT_EQ(testing::ReadBytes(path), "new");
  EXPECT_THROW(WriteWholeFile(path, "the export file",
                              [](const std::string& temporary) {
                                std::ofstream(temporary) << "half";
                                throw InputError(temporary, "cannot write");
                              }),
               InputError);
  EXPECT_EQ(testing::ReadBytes(path), "new");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir_.path())) files += !entry.is_directory();
  EXPECT_EQ(files, 2) << "the partial file was left";  // out.json and map.db
  // The writer sees a path with the target's extension (OpenCV picks the format by it).
  std::string seen;
  WriteWholeFile(dir_.File("image.png"), "the image", [&](const std::string& temporary) {
    seen = temporary;
    std::ofstream(temporary) << "png";
  });
  EXPECT_EQ(fs::path(seen).extension(), ".png");
  EXPECT_EQ(fs::path(seen).parent_path(), dir_.path());
  try {
    WriteWholeFile(dir_.File("missing/out.json"), "the export file", std::string("x"));
    ADD_FAILURE() << "a missing folder was written";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), dir_.File("missing/out.json") +
                                             ": cannot write the export file: the folder " +
                                             dir_.File("missing") + " does not exist");
  }
}

}  // namespace
}  // namespace memloop
