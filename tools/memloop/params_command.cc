// memloop params [--json | --markdown]: every parameter from the one registry.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "memloop/params.h"

namespace memloop::cli {
namespace {

void PrintTable() {
  const Options defaults;
  std::printf("%-30s %-8s %-8s %-10s %-16s %s\n", "NAME", "DEFAULT", "TYPE", "UNIT", "RANGE",
              "DESCRIPTION");
  for (const Parameter& p : Parameters()) {
    std::string description = p.description;
    if (!p.symbol.empty()) description = "[" + p.symbol + "] " + description;
    std::printf("%-30s %-8s %-8s %-10s %-16s %s\n", p.key.c_str(), p.Get(defaults).c_str(),
                p.TypeName().c_str(), p.unit.c_str(), p.RangeText().c_str(), description.c_str());
  }
}

// The default as a JSON value of its type: true, 20, 0.2, "surf".
nlohmann::json DefaultValue(const Parameter& p, const Options& defaults) {
  const std::string text = p.Get(defaults);
  if (p.flag) return text == "true";
  if (p.TypeName() == "int") return std::stoll(text);
  if (p.TypeName() == "double") return std::stod(text);
  return text;
}

void PrintJson() {
  const Options defaults;
  nlohmann::json rows = nlohmann::json::array();
  for (const Parameter& p : Parameters()) {
    rows.push_back({{"name", p.key},
                    {"default", DefaultValue(p, defaults)},
                    {"type", p.TypeName()},
                    {"unit", p.unit},
                    {"range", p.RangeText()},
                    {"symbol", p.symbol},
                    {"description", p.description}});
  }
  std::cout << rows.dump(2) << "\n";
}

}  // namespace

void AddParamsCommand(CLI::App& app) {
  auto format = std::make_shared<std::string>("table");
  CLI::App* params = app.add_subcommand("params", "List every parameter with default and range");
  auto* group = params->add_option_group("format");
  group->add_flag_callback(
      "--json", [format] { *format = "json"; }, "JSON array");
  group->add_flag_callback(
      "--markdown", [format] { *format = "markdown"; }, "Markdown table");
  group->require_option(0, 1);
  params->callback([format] {
    if (*format == "json") {
      PrintJson();
    } else if (*format == "markdown") {
      std::cout << ParametersMarkdown();
    } else {
      PrintTable();
    }
  });
}

}  // namespace memloop::cli
