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
void AddInspectCommand(CLI::App& app);
void AddExportCommand(CLI::App& app);
void AddViewCommand(CLI::App& app);
void AddFleetCommand(CLI::App& app);

// `options` (a preset's, or a map's) with the parameter file `config_path` ("" = none), then each
// "--set NAME=VALUE" in order, applied: later settings win. Throws memloop::Error.
Options WithSettings(Options options, const std::string& config_path,
                     const std::vector<std::string>& assignments);
// --config FILE on `command`.
CLI::Option* AddConfigOption(CLI::App& command, std::string* path);
// --preset NAME on `command`.
CLI::Option* AddPresetOption(CLI::App& command, std::string* name);
// --realtime-priority N on `command` (SessionOptions::realtime_priority).
CLI::Option* AddRealtimePriorityOption(CLI::App& command, int* priority);
// --pace HZ on `command` (SessionOptions::pace_hz).
CLI::Option* AddPaceOption(CLI::App& command, double* hz);

}  // namespace memloop::cli
