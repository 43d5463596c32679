// The subcommands of the `mbrt` command, one file each.
#pragma once

#include <CLI/CLI.hpp>

namespace mbrt::tools {

void registerStatsCommand(CLI::App& app);
void registerTraceCommand(CLI::App& app);
void registerRenderCommand(CLI::App& app);
void registerBenchCommand(CLI::App& app);
void registerInfoCommand(CLI::App& app);

}  // namespace mbrt::tools
