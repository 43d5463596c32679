// The `mbrt` command: one subcommand per file (commands.h). Exit codes: 0
// success, 1 failure (bad file, I/O error, a build over its memory budget),
// 2 usage error (bad option, unknown scene or kind), 130 / 143 stopped by
// SIGINT / SIGTERM after writing the partial result (render).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <new>

#include "commands.h"
#include "mpi_frames.h"
#include "mbrt/scene.h"
#include "scene_loading.h"

#ifndef MBRT_VERSION
#define MBRT_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  const mbrt::tools::MpiSession mpi(argc, argv);  // under mpirun (MBRT_MPI builds)
  CLI::App app{"mbrt: motion-blur ray tracing kernel (structures, tracing, rendering)", "mbrt"};
  app.set_version_flag("--version", std::string("mbrt ") + MBRT_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);

  try {
    mbrt::tools::registerStatsCommand(app);
    mbrt::tools::registerTraceCommand(app);
    mbrt::tools::registerRenderCommand(app);
    mbrt::tools::registerBenchCommand(app);
    mbrt::tools::registerInfoCommand(app);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::fprintf(stderr, "mbrt: error: %s\nRun 'mbrt --help' or 'mbrt SUBCOMMAND --help' for usage.\n", e.what());
    return 2;
  } catch (const mbrt::tools::ExitStatus& e) {
    return e.code();
  } catch (const mbrt::tools::UsageError& e) {
    std::fprintf(stderr, "mbrt: error: %s\n", e.what());
    return 2;
  } catch (const mbrt::Error& e) {
    std::fprintf(stderr, "mbrt: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "mbrt: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mbrt: error: %s\n", e.what());
    return 1;
  } catch (...) {
    std::fprintf(stderr, "mbrt: error: unknown exception\n");
    return 1;
  }
  return 0;
}
