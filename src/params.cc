#include "memloop/params.h"

#include <cmath>
#include <sstream>

#include "memloop/errors.h"

namespace memloop {
namespace {

#define MEMLOOP_FIELD(path)   \
  +[](Options & o) -> auto& { \
    return o.path;            \
  }

std::vector<Parameter> MakeRegistry() {
  constexpr double kHuge = 1e9;
  return {
      {"features.type",
       MEMLOOP_FIELD(features.type),
       "",
       0,
       0,
       false,
       {"sift"},
       "",
       "Feature backend: sift (OpenCV SIFT, 128-d float descriptors)"},
      {"features.max_features",
       MEMLOOP_FIELD(features.max_features),
       "keypoints",
       0,
       100000,
       false,
       {},
       "",
       "Strongest keypoints kept per image (0 = all)"},
      {"dictionary.nndr_ratio",
       MEMLOOP_FIELD(dictionary.nndr_ratio),
       "",
       0,
       1,
       true,
       {},
       "",
       "Nearest-neighbour distance ratio (true L2): d1 < ratio*d2 joins a word, else a new word"},
      {"dictionary.kd_trees",
       MEMLOOP_FIELD(dictionary.kd_trees),
       "trees",
       1,
       64,
       false,
       {},
       "",
       "Randomized kd-trees in the dictionary's forest (FLANN)"},
      {"dictionary.kd_checks",
       MEMLOOP_FIELD(dictionary.kd_checks),
       "leaves",
       1,
       100000,
       false,
       {},
       "",
       "Leaves visited per nearest-neighbour search (FLANN checks)"},
      {"dictionary.rebuild_fraction",
       MEMLOOP_FIELD(dictionary.rebuild_fraction),
       "",
       0,
       100,
       true,
       {},
       "",
       "Rebuild the forest when points added+removed since the last build exceed "
       "this fraction of its size then"},
      {"dictionary.seed",
       MEMLOOP_FIELD(dictionary.seed),
       "",
       0,
       2147483647,
       false,
       {},
       "",
       "Seed of the forest's random splits (repeatable runs)"},
      {"memory.stm_size",
       MEMLOOP_FIELD(memory.stm_size),
       "locations",
       0,
       100000,
       false,
       {},
       "STM size",
       "Newest locations kept out of loop closure detection"},
      {"memory.rehearsal_threshold",
       MEMLOOP_FIELD(memory.rehearsal_threshold),
       "",
       0,
       1,
       false,
       {},
       "T_rehearsal (eq. 1)",
       "Similarity above which the compared STM location is merged"},
      {"memory.time_limit_ms",
       MEMLOOP_FIELD(memory.time_limit_ms),
       "ms",
       0,
       kHuge,
       false,
       {},
       "T_time",
       "Iteration time above which WM locations go to LTM (0 = infinity)"},
      {"memory.max_wm_locations",
       MEMLOOP_FIELD(memory.max_wm_locations),
       "locations",
       0,
       kHuge,
       false,
       {},
       "",
       "Deterministic budget: transfer while WM is larger (0 = none)"},
      {"memory.max_dictionary_words",
       MEMLOOP_FIELD(memory.max_dictionary_words),
       "words",
       0,
       kHuge,
       false,
       {},
       "",
       "Deterministic budget: transfer while the dictionary is larger "
       "(0 = none)"},
      {"memory.max_retrieved",
       MEMLOOP_FIELD(memory.max_retrieved),
       "locations",
       0,
       1000,
       false,
       {},
       "",
       "Locations retrieved from LTM per iteration, at most"},
      {"filter.loop_threshold",
       MEMLOOP_FIELD(filter.loop_threshold),
       "",
       0,
       1,
       false,
       {},
       "T_loop",
       "Neighbour-summed posterior above which a loop closure is accepted"},
      {"filter.min_hypotheses",
       MEMLOOP_FIELD(filter.min_hypotheses),
       "locations",
       0,
       100000,
       false,
       {},
       "T_minHyp",
       "WM locations needed before a loop closure can be accepted"},
      {"filter.virtual_place_stay",
       MEMLOOP_FIELD(filter.virtual_place_stay),
       "",
       0,
       1,
       false,
       {},
       "p(S_t=-1|S_t-1=-1)",
       "Transition: new location after new location (1 - it: to a "
       "loop closure)"},
      {"filter.neighbour_range",
       MEMLOOP_FIELD(filter.neighbour_range),
       "links",
       0,
       100,
       false,
       {},
       "",
       "Transition and hypothesis sum reach this many links from a location"},
      {"filter.neighbour_sigma",
       MEMLOOP_FIELD(filter.neighbour_sigma),
       "links",
       0,
       100,
       true,
       {},
       "",
       "Standard deviation of the transition model's discretized Gaussian"},
  };
}

#undef MEMLOOP_FIELD

std::string FormatDouble(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Strict parse: the whole text must be the number.
bool ParseDouble(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*value);
}

}  // namespace

std::string Parameter::TypeName() const {
  switch (field.index()) {
    case 0:
      return "int";
    case 1:
      return "double";
    default:
      return "string";
  }
}

std::string Parameter::Get(const Options& options) const {
  Options& mutable_options = const_cast<Options&>(options);  // accessors only read here
  return std::visit(
      [&](auto accessor) -> std::string {
        const auto& value = accessor(mutable_options);
        if constexpr (std::is_same_v<std::decay_t<decltype(value)>, std::string>) {
          return value;
        } else {
          return FormatDouble(value);
        }
      },
      field);
}

std::string Parameter::RangeText() const {
  if (!choices.empty()) {
    std::string text;
    for (const auto& choice : choices) text += (text.empty() ? "" : "|") + choice;
    return text;
  }
  return (min_exclusive ? "(" : "[") + FormatDouble(min) + ", " + FormatDouble(max) + "]";
}

std::string Parameter::Check(const Options& options) const {
  const std::string value = Get(options);
  if (!choices.empty()) {
    for (const auto& choice : choices) {
      if (value == choice) return "";
    }
    return "must be one of " + RangeText();
  }
  double number = 0;
  ParseDouble(value, &number);
  const bool above_min = min_exclusive ? number > min : number >= min;
  if (!above_min || number > max) return "must be in " + RangeText();
  return "";
}

void Parameter::Set(Options& options, const std::string& value) const {
  const auto fail = [&](const std::string& why) {
    throw ParameterError(key, "Invalid parameter " + key + " = '" + value + "': " + why);
  };
  std::visit(
      [&](auto accessor) {
        auto& target = accessor(options);
        using T = std::decay_t<decltype(target)>;
        if constexpr (std::is_same_v<T, std::string>) {
          target = value;
        } else {
          double number = 0;
          if (!ParseDouble(value, &number)) fail("not a number");
          if (std::is_same_v<T, int> && number != std::floor(number)) fail("not a whole number");
          if (std::is_same_v<T, int> && std::fabs(number) > 2147483647.0) fail("out of range");
          target = static_cast<T>(number);
        }
      },
      field);
  const std::string problem = Check(options);
  if (!problem.empty()) fail(problem);
}

const std::vector<Parameter>& Parameters() {
  static const std::vector<Parameter> registry = MakeRegistry();
  return registry;
}

const Parameter* FindParameter(const std::string& key) {
  for (const auto& parameter : Parameters()) {
    if (parameter.key == key) return &parameter;
  }
  return nullptr;
}

void SetParameter(Options& options, const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw ParameterError(assignment, "Malformed parameter '" + assignment +
                                         "': expected NAME=VALUE (see 'memloop params')");
  }
  const std::string key = assignment.substr(0, equals);
  const Parameter* parameter = FindParameter(key);
  if (parameter == nullptr) {
    throw ParameterError(key, "Unknown parameter '" + key + "' (see 'memloop params')");
  }
  parameter->Set(options, assignment.substr(equals + 1));
}

void ValidateOptions(const Options& options) {
  for (const auto& parameter : Parameters()) {
    const std::string problem = parameter.Check(options);
    if (!problem.empty()) {
      throw ParameterError(parameter.key, "Invalid parameter " + parameter.key + " = " +
                                              parameter.Get(options) + ": " + problem);
    }
  }
}

std::string ParametersMarkdown() {
  const Options defaults;
  std::ostringstream out;
  out << "# Parameters\n\n"
         "Generated by `memloop params --markdown` from the parameter registry (src/params.cc); "
         "a test keeps this file in step with it. Set any of them with `--set NAME=VALUE`. "
         "Defaults are the paper's values where it gives one (Sec. IV).\n\n"
         "| name | default | type | unit | range | paper | description |\n"
         "| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Parameter& p : Parameters()) {
    out << "| `" << p.key << "` | " << p.Get(defaults) << " | " << p.TypeName() << " | " << p.unit
        << " | " << p.RangeText() << " | " << p.symbol << " | " << p.description << " |\n";
  }
  return out.str();
}

}  // namespace memloop
