// The perifrac command line: run a scene, benchmark the kernels, list devices.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <new>
#include <stdexcept>
#include <string>

#include "cuda/engine/engine.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/parallel/comm.h"
#include "host/app/checkpoint.h"
#include "host/app/run_folder.h"
#include "host/cli/command_line.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene.h"

namespace pd {

namespace {

// Runs a subcommand: its exit code, or the one of the error it throws, reported in one line.
int report_errors(const std::function<int()>& action) {
  try {
    return action();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResourceError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResumeError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const RunFolderError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const IoError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRuntime;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::bad_alloc&) {  // (what a check before an allocation did not foresee)
    std::fprintf(stderr,
                 "error: out of memory: the command needs more host memory than is free (allowed: a "
                 "larger spacing, a smaller --scale, --resolution or --lattice, or a machine with "
                 "more memory)\n");
    return kExitUsage;
  } catch (const std::length_error&) {
    std::fprintf(stderr,
                 "error: out of memory: the command asked for an array larger than any machine holds "
                 "(allowed: a larger spacing or cell, a smaller --scale, --resolution or --lattice)\n");
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRuntime;
  }
}

// The commands of host/app, for the command line to run.
CommandActions command_actions() {
  CommandActions a;
  a.run = run_command;
  a.bench = bench_command;
  a.bench_render = bench_render_command;
  a.bench_geometry = bench_geometry_command;
  a.shapes = export_shapes_command;
  a.bench_fragments = bench_fragments_command;
  a.profile = profile_command;
  a.validate = validate_command;
  a.render = render_frames;
  a.compare = compare_command;
  a.info = [] {
    std::string why;
    const bool gpu = cuda_device_available(&why);
    std::printf("perifrac %s\ncpu   available\ncuda  %s\n", PERIFRAC_VERSION,
                gpu ? "available" : why.c_str());
    return int(kExitOk);
  };
  return a;
}

}  // namespace

}  // namespace pd

int main(int argc, char** argv) {
  using namespace pd;
  // Under mpirun, rank 0 runs the command and the engine's other ranks serve it
  // (cuda/parallel/partitioned_engine.h): they print nothing but errors.
  if (const auto world = world_comm()) {
    // Every rank runs the same command (one scene, scale and --set values): a rank started with
    // other arguments would take another set-up and hang or garble the collective steps. Checked
    // first, so that every rank takes the same way out of what follows.
    std::string line;
    for (int k = 1; k < argc; ++k) line += std::string(argv[k]) + '\0';
    const uint64_t mine = std::hash<std::string>{}(line);
    uint64_t first = mine;
    world->broadcast(&first, sizeof first, 0);
    if (world->bit_or(first != mine ? 1u : 0u) != 0) {
      if (first != mine)
        std::fprintf(stderr,
                     "error: under mpirun every rank must be started with the same arguments; rank %d's "
                     "differ from rank 0's (allowed: mpirun -np N perifrac run SCENE [options], one command "
                     "for all ranks)\n",
                     world->rank());
      leave_world();
      return int(kExitUsage);
    }
    const std::string command = argc > 1 ? argv[1] : "";
    if (command != "run" && command != "bench") {
      if (world->rank() == 0)
        std::fprintf(stderr,
                     "error: under mpirun only `perifrac run` and `perifrac bench` use the ranks; "
                     "start `perifrac %s` without mpirun\n",
                     command.c_str());
      leave_world();
      return int(kExitUsage);
    }
    if (world->rank() != 0 && !std::freopen("/dev/null", "w", stdout)) {
      leave_world();
      return int(kExitRuntime);
    }
  }
  CLI::App app{"perifrac: peridynamic fracture simulation on GPU and CPU"};
  const CommandActions actions = command_actions();
  std::function<int()> chosen;
  add_commands(app, actions, &chosen);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // a command-line mistake: one line, exit code 2
    const std::string unknown = unknown_command_error(app, argc > 1 ? argv[1] : "");
    std::fprintf(stderr, "%s\n", unknown.empty() ? command_line_error(e).c_str() : unknown.c_str());
    leave_world();
    return kExitUsage;
  }
  int exit_code = chosen ? report_errors(chosen) : int(kExitUsage);
  // What the command printed must have reached its reader (a full disk, /dev/full).
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "error: cannot write the standard output: %s\n",
                 errno != 0 ? std::strerror(errno) : "write error");
    if (exit_code == kExitOk) exit_code = kExitRuntime;
  }
  leave_world();
  return exit_code;
}
