#include "memloop/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <utility>
#include <vector>

#include "memloop/errors.h"

namespace memloop {
namespace {

std::string ErrorOf(const std::string& assignment) {
  Options options;
  try {
    SetParameter(options, assignment);
  } catch (const ParameterError& error) {
    return error.what();
  }
  return "";
}

TEST(ParamsTest, Paper2011PresetIsThePapersAndValid) {
  const Options options = Options::Paper2011();
  EXPECT_NO_THROW(ValidateOptions(options));
  EXPECT_EQ(FindParameter("memory.stm_size")->Get(options), "25");
  EXPECT_EQ(FindParameter("surf.upright")->Get(options), "false");
  EXPECT_EQ(FindParameter("filter.hypothesis_value")->Get(options), "best_neighbours");
  EXPECT_EQ(FindParameter("filter.likelihood")->Get(options), "similarity");
  // Where the text is silent, the paper's 2011 code (introlab/rtabmap 2d73090f, docs/design.md).
  EXPECT_EQ(FindParameter("surf.hessian_threshold")->Get(options), "100");
  EXPECT_EQ(FindParameter("surf.sample_step")->Get(options), "1");
  EXPECT_EQ(FindParameter("dictionary.kd_checks")->Get(options), "64");
  EXPECT_EQ(FindParameter("memory.rehearsal_most_similar")->Get(options), "true");
  EXPECT_EQ(FindParameter("filter.loop_ratio")->Get(options), "0.9");
  EXPECT_EQ(FindParameter("filter.no_signal_virtual_place")->Get(options), "2");
  EXPECT_EQ(FindParameter("filter.min_shared_words")->Get(options), "1");
  EXPECT_EQ(FindParameter("memory.retrieved_immune_iterations")->Get(options), "10");
  EXPECT_EQ(FindParameter("filter.require_support")->Get(options), "false");
  EXPECT_EQ(FindParameter("filter.ltm_neighbour_check")->Get(options), "false");
  EXPECT_EQ(FindParameter("memory.protect_hypothesis")->Get(options), "false");
  EXPECT_EQ(FindParameter("memory.time_target")->Get(options), "1");
  EXPECT_EQ(FindParameter("verify.min_inliers")->Get(options), "0");
  EXPECT_EQ(FindParameter("memory.rehearsal_threshold")->Get(options), "0.2");
  EXPECT_EQ(FindParameter("filter.loop_threshold")->Get(options), "0.1");
  EXPECT_EQ(FindParameter("filter.min_hypotheses")->Get(options), "15");
  EXPECT_EQ(FindParameter("memory.max_retrieved")->Get(options), "2");
  EXPECT_EQ(FindParameter("dictionary.kd_trees")->Get(options), "4");
  // 0.8 on squared distances.
  EXPECT_NEAR(std::stod(FindParameter("dictionary.nndr_ratio")->Get(options)), std::sqrt(0.8),
              1e-9);
}

// The defaults differ from the paper only where docs/design.md says so and measures it.
TEST(ParamsTest, DefaultsDepartFromThePaperOnlyWhereDocumented) {
  const Options defaults;
  EXPECT_NO_THROW(ValidateOptions(defaults));
  const Options paper = Options::Paper2011();
  std::set<std::string> departures;
  for (const Parameter& parameter : Parameters()) {
    if (parameter.Get(defaults) != parameter.Get(paper)) departures.insert(parameter.key);
  }
  EXPECT_EQ(departures,
            (std::set<std::string>{
                "surf.upright", "memory.stm_size", "memory.protect_hypothesis",
                "filter.loop_threshold", "filter.hypothesis_value", "filter.require_support",
                "filter.min_shared_words", "filter.ltm_neighbour_check",
                "filter.support_from_image", "memory.time_target", "memory.transfer_max_fraction",
                "sift.upright", "orb.upright", "memory.appearance_retrieval",
                "memory.retrieval_within_time", "memory.retrieval_read_ahead",
                "memory.signature_within_time", "memory.retrieval_over_iterations",
                "memory.retrieval_kd_checks", "memory.max_dictionary_words",
                "memory.retrieval_min_value", "memory.retrieved_kept_last_iterations",
                "memory.retrieval_strong_value", "memory.signature_room_for_retrieval",
                "memory.retrieval_stage_deferred", "features.min_image_side",
                // The paper's 2011 code where its text is silent; memloop's measured choices.
                "surf.hessian_threshold", "surf.sample_step", "surf.rolled_view_degrees",
                "dictionary.nndr_ratio", "dictionary.kd_checks", "memory.rehearsal_most_similar",
                "filter.loop_ratio", "filter.no_signal_virtual_place", "filter.min_sigma_ratio",
                "memory.retrieved_immune_iterations", "memory.wm_min_time_share"}));
}

TEST(ParamsTest, PresetsByName) {
  EXPECT_EQ(Preset("default").memory.stm_size, Options().memory.stm_size);
  // verified: the defaults with verification under T_loop, all valid; the defaults keep it off.
  const Options verified = Preset("verified");
  EXPECT_EQ(verified.verification.loop_threshold, 0.05);
  EXPECT_EQ(verified.verification.correspondences, "descriptors");
  EXPECT_EQ(verified.filter.loop_threshold, Options().filter.loop_threshold);
  EXPECT_EQ(Options().verification.min_inliers, 0);
  for (const Parameter& parameter : Parameters()) {
    EXPECT_TRUE(parameter.Check(verified).empty()) << parameter.key;
  }
  EXPECT_EQ(Preset("paper2011").filter.hypothesis_value, "best_neighbours");
  EXPECT_THROW(Preset("paper2013"), ParameterError);
  // hand-held: the defaults with the roll compensated and views rolled apart refused, all valid.
  const Options hand_held = Preset("hand-held");
  EXPECT_EQ(hand_held.features.surf_max_roll_degrees, 45);
  EXPECT_EQ(hand_held.verification.max_roll_degrees, 20);
  EXPECT_EQ(hand_held.filter.support_from_image, 2);  // as the defaults
  EXPECT_EQ(Options().filter.support_from_image, 2);
  EXPECT_EQ(Preset("paper2011").filter.support_from_image, 0);
  EXPECT_EQ(hand_held.filter.cap_merged_images, 1);
  EXPECT_EQ(Options().filter.cap_merged_images, 0);
  EXPECT_EQ(hand_held.memory.stm_size, Options().memory.stm_size);
  for (const Parameter& parameter : Parameters()) {
    EXPECT_TRUE(parameter.Check(hand_held).empty()) << parameter.key;
  }
  // day-night: the defaults with the whole-image channel; the defaults keep it off.
  const Options day_night = Preset("day-night");
  EXPECT_EQ(day_night.features.whole_image, 1);
  EXPECT_EQ(Options().features.whole_image, 0);
  EXPECT_EQ(day_night.filter.loop_threshold, Options().filter.loop_threshold);
  for (const Parameter& parameter : Parameters()) {
    EXPECT_TRUE(parameter.Check(day_night).empty()) << parameter.key;
  }
}

TEST(ParamsTest, EveryParameterIsDescribed) {
  for (const Parameter& parameter : Parameters()) {
    EXPECT_FALSE(parameter.description.empty()) << parameter.key;
    EXPECT_TRUE(parameter.Check(Options()).empty()) << parameter.key;
  }
}

TEST(ParamsTest, SetStoresTheValue) {
  Options options;
  SetParameter(options, "memory.stm_size=30");
  SetParameter(options, "filter.loop_threshold=0.25");
  EXPECT_EQ(options.memory.stm_size, 30);
  EXPECT_DOUBLE_EQ(options.filter.loop_threshold, 0.25);
}

TEST(ParamsTest, BadAssignmentsAreRefusedWithTheReason) {
  EXPECT_EQ(ErrorOf("memory.stm_size=-1"),
            "Invalid parameter memory.stm_size = '-1': must be in [1, 100000]");
  // STM 0 would put L_t in WM before it is scored: it would match itself.
  EXPECT_NE(ErrorOf("memory.stm_size=0").find("must be in [1, 100000]"), std::string::npos);
  EXPECT_NE(ErrorOf("filter.loop_threshold=1.5").find("must be in [0, 1]"), std::string::npos);
  EXPECT_NE(ErrorOf("dictionary.nndr_ratio=0").find("must be in (0, 1]"), std::string::npos);
  EXPECT_NE(ErrorOf("memory.stm_size=2.5").find("not a whole number"), std::string::npos);
  EXPECT_NE(ErrorOf("memory.stm_size=lots").find("not a number"), std::string::npos);
  EXPECT_NE(ErrorOf("memory.stm_size=").find("not a number"), std::string::npos);
  EXPECT_NE(ErrorOf("features.type=surfish").find("must be one of surf|sift|orb"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("memory.stm=3"), "Unknown parameter 'memory.stm' (see 'memloop params')");
  // A typo names the nearest parameter (here one letter missing).
  EXPECT_EQ(ErrorOf("memory.time_limt_ms=3"),
            "Unknown parameter 'memory.time_limt_ms' (see 'memloop params'); did you mean "
            "'memory.time_limit_ms'?");
  EXPECT_NE(ErrorOf("stm_size").find("expected NAME=VALUE"), std::string::npos);
}

// Values are kept at full precision (a map stores them as text and reads them back).
TEST(ParamsTest, ValuesRoundTripAtFullPrecision) {
  Options options;
  SetParameter(options, "dictionary.seed=1234567");
  SetParameter(options, "filter.loop_threshold=0.123456789012");
  const Parameter* seed = FindParameter("dictionary.seed");
  const Parameter* threshold = FindParameter("filter.loop_threshold");
  EXPECT_EQ(seed->Get(options), "1234567");
  EXPECT_EQ(threshold->Get(options), "0.123456789012");
  EXPECT_EQ(FindParameter("memory.rehearsal_threshold")->Get(Options()), "0.2");
  Options copy;
  threshold->Set(copy, threshold->Get(options));
  EXPECT_EQ(copy.filter.loop_threshold, options.filter.loop_threshold);
}

TEST(ParamsTest, SwitchesAreBooleans) {
  const Parameter* upright = FindParameter("surf.upright");
  EXPECT_EQ(upright->TypeName(), "bool");
  EXPECT_EQ(upright->RangeText(), "true|false");
  Options options;
  for (const auto& [text, value] : std::vector<std::pair<std::string, int>>{
           {"false", 0}, {"TRUE", 1}, {"off", 0}, {"yes", 1}, {"0", 0}, {"1", 1}}) {
    SetParameter(options, "surf.upright=" + text);
    EXPECT_EQ(options.features.surf_upright, value) << text;
    EXPECT_EQ(upright->Get(options), value ? "true" : "false");
  }
  EXPECT_NE(ErrorOf("surf.upright=2").find("not true or false"), std::string::npos);
  options.features.surf_upright = 5;  // through the C++ API
  EXPECT_EQ(upright->Check(options), "must be 0 or 1 (false or true)");
}

TEST(ParamsTest, ParameterFileAppliesThroughTheRegistry) {
  const std::string path = ::testing::TempDir() + "/memloop_params_test.ini";
  std::ofstream(path) << "# a comment\n"
                         "memory.stm_size = 25   ; trailing comment\n"
                         "\n"
                         "[filter]\n"
                         "loop_threshold=0.3\n"
                         "[surf]\n"
                         "upright = false\n";
  Options options;
  ApplyParameterFile(options, path);
  EXPECT_EQ(options.memory.stm_size, 25);
  EXPECT_DOUBLE_EQ(options.filter.loop_threshold, 0.3);
  EXPECT_EQ(options.features.surf_upright, 0);
  const auto error_of = [&](const std::string& text) -> std::string {
    std::ofstream(path) << text;
    try {
      ApplyParameterFile(options, path);
    } catch (const InputError& error) {
      return error.what();
    }
    return "accepted";
  };
  EXPECT_EQ(error_of("memory.stm_size = 20\nmemory.stm = 3\n"),
            path + ": line 2: Unknown parameter 'memory.stm' (see 'memloop params')");
  EXPECT_EQ(error_of("[filter\n"), path + ": line 1: a section must end with ']'");
  EXPECT_EQ(error_of("stm_size 20\n"),
            path + ": line 1: expected 'name = value', got 'stm_size 20'");
  EXPECT_NE(error_of("[memory]\nstm_size = -4\n").find("line 2: Invalid parameter memory.stm_size"),
            std::string::npos);
  EXPECT_NE(error_of("").find("accepted"), std::string::npos);
  // Before: the message stopped at the NUL byte, saying nothing of it, and a 10 MB value was
  // echoed whole.
  EXPECT_EQ(error_of(std::string("memory.stm_size = 20\0garbage\n", 30)),
            path + ": line 1: holds a NUL byte: a parameter file is text");
  EXPECT_EQ(error_of("memory.stm_size = " + std::string(10000000, '9') + "\n"),
            path + ": line 1: Invalid parameter memory.stm_size = '" + std::string(40, '9') +
                "... (10000000 characters)': not a number");
  std::remove(path.c_str());
  try {
    ApplyParameterFile(options, path + ".absent");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ".absent: cannot read the parameter file");
  }
}

TEST(ParamsTest, ValidateFindsAnInvalidField) {
  Options options;
  options.memory.max_retrieved = -3;
  try {
    ValidateOptions(options);
    FAIL();
  } catch (const ParameterError& error) {
    EXPECT_EQ(error.key(), "memory.max_retrieved");
  }
}

TEST(ParamsTest, DocsAreGeneratedFromTheRegistry) {
  std::ifstream file(std::string(MEMLOOP_SOURCE_DIR) + "/docs/parameters.md");
  ASSERT_TRUE(file) << "docs/parameters.md is missing";
  const std::string text(std::istreambuf_iterator<char>(file), {});
  EXPECT_EQ(text, ParametersMarkdown())
      << "regenerate: ./build/memloop params --markdown > docs/parameters.md";
}

}  // namespace
}  // namespace memloop
