// `mbrt bench` (placeholder until the benchmark lands).
#include <cstdio>

#include "commands.h"

namespace mbrt::tools {

void registerBenchCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "Benchmark every structure (not yet available)");
  cmd->callback([] { std::fprintf(stderr, "mbrt bench: not implemented yet\n"); });
}

}  // namespace mbrt::tools
