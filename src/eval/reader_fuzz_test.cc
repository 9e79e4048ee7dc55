// The readers of user files (run CSVs, ground truth as pairs or a text matrix) under random
// mutations of valid files: each mutant is read and evaluated, and the only way to fail is a
// memloop::Error (one clear line); never a crash, a bare std:: exception, or a huge allocation.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/ground_truth.h"
#include "memloop/run_csv.h"
#include "temp_dir.h"

namespace memloop {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A valid run of 12 images with a few loop closures.
std::string ValidRunCsv(const std::string& path) {
  RunCsvWriter writer(path);
  for (int image = 0; image < 12; ++image) {
    Result result;
    result.processed = true;
    result.image_index = image;
    result.location_id = image + 1;
    result.hypothesis_id = image > 2 ? image - 2 : kNoLocation;
    result.hypothesis_value = image > 2 ? 0.05 * image : 0;
    if (image > 2) result.hypothesis_images = {image - 3};
    if (image > 8) {
      result.loop_closure_id = image - 8;
      result.loop_closure_images = {image - 9};
    }
    result.wm_size = image;
    writer.Write(std::to_string(image + 1) + ".png", result);
  }
  writer.Close();
  return ReadText(path);
}

std::string Mutate(std::string text, std::mt19937& random) {
  static const std::vector<std::string> kPieces = {
      "-",  "-5", "nan",   "inf", "1.5", "1e308", "99999999999", ",",    ";",         "\"",
      "\n", "",   "30000", "0",   "-1;", "255",   " ",           "\r\n", "2147483648"};
  const int edits = 1 + static_cast<int>(random() % 4);
  for (int edit = 0; edit < edits && !text.empty(); ++edit) {
    const size_t at = random() % text.size();
    switch (random() % 5) {
      case 0:  // replace a byte
        text[at] = static_cast<char>(random() % 256);
        break;
      case 1:  // insert a troublesome piece
        text.insert(at, kPieces[random() % kPieces.size()]);
        break;
      case 2:  // delete a run
        text.erase(at, 1 + random() % 8);
        break;
      case 3:  // truncate
        text.resize(at);
        break;
      default: {  // duplicate a line
        const size_t start = text.rfind('\n', at);
        const size_t end = text.find('\n', at);
        if (start != std::string::npos && end != std::string::npos) {
          text.insert(end, text.substr(start, end - start));
        }
      }
    }
  }
  return text;
}

// eval's own path: read the run, then the ground truth sized by the run, then evaluate.
void ReadAndEvaluate(const std::string& run_path, const std::string& truth_path,
                     GroundTruthFormat format) {
  const std::vector<RunRow> rows = ReadRunCsv(run_path);
  const int image_count = rows.back().image + 1;
  std::vector<std::string> names(image_count);
  for (const RunRow& row : rows) names[row.image] = row.name;
  const GroundTruth truth = GroundTruth::Load(truth_path, format, names, image_count);
  EvaluateRun(rows, truth);
}

TEST(ReaderFuzzTest, MutatedRunCsvsAndGroundTruthFailOnlyWithAClearError) {
  testing::TempDir dir;
  const std::string run = dir.File("run.csv");
  const std::string pairs = dir.File("truth.csv");
  const std::string matrix = dir.File("truth.txt");
  const std::string valid_run = ValidRunCsv(run);
  std::string valid_pairs = "query,match\n";
  for (int image = 9; image < 12; ++image) {
    valid_pairs += std::to_string(image + 1) + ".png," + std::to_string(image - 8) + ".png\n";
  }
  std::string valid_matrix;
  for (int a = 0; a < 12; ++a) {
    for (int b = 0; b < 12; ++b) valid_matrix += (a - b == 9 || b - a == 9) ? "1 " : "0 ";
    valid_matrix += "\n";
  }
  WriteText(pairs, valid_pairs);
  WriteText(matrix, valid_matrix);
  ASSERT_NO_THROW(ReadAndEvaluate(run, pairs, GroundTruthFormat::kPairs));
  ASSERT_NO_THROW(ReadAndEvaluate(run, matrix, GroundTruthFormat::kMatrix));

  std::mt19937 random(2026);
  int refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int target = trial % 3;  // the run, the pairs or the matrix
    WriteText(run, target == 0 ? Mutate(valid_run, random) : valid_run);
    WriteText(pairs, target == 1 ? Mutate(valid_pairs, random) : valid_pairs);
    WriteText(matrix, target == 2 ? Mutate(valid_matrix, random) : valid_matrix);
    const std::string& truth = target == 2 ? matrix : pairs;
    const auto format = target == 2 ? GroundTruthFormat::kMatrix : GroundTruthFormat::kPairs;
    try {
      ReadAndEvaluate(run, truth, format);
    } catch (const Error& error) {
      ++refused;
      EXPECT_NE(std::string(error.what()).find(dir.path().string()), std::string::npos)
          << "the message names no file: " << error.what();
    } catch (const std::exception& error) {
      ADD_FAILURE() << "trial " << trial << ": " << typeid(error).name() << ": " << error.what()
                    << "\n"
                    << ReadText(target == 0 ? run : truth);
    }
  }
  EXPECT_GT(refused, 500);  // the mutations do reach the checks
}

}  // namespace
}  // namespace memloop
