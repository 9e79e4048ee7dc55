// The parameter registry: one row per parameter (key, type, default, unit, range, paper symbol,
// description). Defaults are read from a default-constructed Options, so they cannot drift.
// `memloop params`, `--set NAME=VALUE`, Options validation and docs/parameters.md all come from it.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "memloop/options.h"

namespace memloop {

struct Parameter {
  using Accessor =
      std::variant<int& (*)(Options&), double& (*)(Options&), std::string& (*)(Options&)>;

  std::string key;   // "memory.stm_size"
  Accessor field;    // where the value lives in Options
  std::string unit;  // "locations", "ms", "" ...
  double min = 0;    // numeric range [min, max] (min excluded when min_exclusive)
  double max = 0;
  bool min_exclusive = false;
  bool flag = false;                 // an int field used as a boolean: "true" / "false"
  std::vector<std::string> choices;  // allowed values of a string parameter
  std::string symbol;                // the paper's symbol or equation, "" when none
  std::string description;           // one line

  // Features, SURF and dictionary parameters: they define what a stored word means and how
  // words are found, so a map keeps them (resuming with another value is refused).
  bool DefinesMap() const;
  std::string TypeName() const;                   // "int", "double", "string", "bool"
  std::string Get(const Options& options) const;  // value as text
  std::string RangeText() const;                  // "[0, 1]", "(0, 1]", "sift|orb"
  // Parses and range-checks `value`, then stores it. Throws ParameterError naming key and value.
  void Set(Options& options, const std::string& value) const;
  // Empty when the value in `options` is valid, else the reason.
  std::string Check(const Options& options) const;
};

// Every parameter, in display order.
const std::vector<Parameter>& Parameters();
// nullptr when `key` is unknown.
const Parameter* FindParameter(const std::string& key);
// Applies "NAME=VALUE". Throws ParameterError for an unknown name, a malformed or invalid value.
void SetParameter(Options& options, const std::string& assignment);
// Applies a parameter file, in order: INI lines "name = value", or "[section]" then
// "name = value" for "section.name"; comments from '#' or ';' (at the start or after a blank);
// blank lines. Throws InputError naming the file and the line (unknown name, invalid value,
// malformed line).
void ApplyParameterFile(Options& options, const std::string& path);
// Throws ParameterError for the first invalid value, e.g.
// "Invalid parameter memory.stm_size = -1: must be in [0, 100000]".
void ValidateOptions(const Options& options);

// docs/parameters.md: the registry as a Markdown table (`memloop params --markdown`).
std::string ParametersMarkdown();

}  // namespace memloop
