// The subcommands of the memloop tool, one file each.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "memloop/options.h"

namespace memloop::cli {

// Each Add*Command registers its subcommand; the callback runs it and may throw memloop::Error.
void AddRunCommand(CLI::App& app);
void AddDemoCommand(CLI::App& app);
void AddParamsCommand(CLI::App& app);
void AddEvalCommand(CLI::App& app);
void AddReportCommand(CLI::App& app);

// Default options with every "--set NAME=VALUE" applied (throws ParameterError).
// The preset ("default" or "paper2011"), then each NAME=VALUE in order.
Options OptionsFromAssignments(const std::vector<std::string>& assignments,
                               const std::string& preset = "default");

}  // namespace memloop::cli
