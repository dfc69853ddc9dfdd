// The perifrac command line (CLI11): every subcommand with its options, checked as they are parsed.
// Parsing runs nothing: the chosen subcommand's action, bound to its options, is handed back to
// run afterwards, so the parser stands alone (main.cpp runs the commands; the fuzz target
// tests/fuzz/fuzz_command_line.cpp only parses).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "host/app/bench.h"
#include "host/app/bench_fragments.h"
#include "host/app/bench_geometry.h"
#include "host/app/bench_render.h"
#include "host/app/compare.h"
#include "host/app/export_shapes.h"
#include "host/app/profile.h"
#include "host/app/render_frames.h"
#include "host/app/run.h"
#include "host/app/validate_command.h"

namespace pd {

// What each subcommand runs with its parsed options (host/app's commands in main.cpp).
struct CommandActions {
  std::function<int(const RunOptions&)> run;
  std::function<int(const BenchOptions&)> bench;
  std::function<int(const RenderBenchOptions&)> bench_render;
  std::function<int(const GeometryBenchOptions&)> bench_geometry;
  std::function<int(const ShapeExportOptions&)> shapes;
  std::function<int(const FragmentsBenchOptions&)> bench_fragments;
  std::function<int(const ProfileOptions&)> profile;
  std::function<int(const ValidateOptions&)> validate;
  std::function<int(const RenderOptions&)> render;
  std::function<int(const CompareOptions&)> compare;
  std::function<int()> info;
};

// Adds the subcommands to `app`, in the order `perifrac --help` lists them. Once app.parse()
// returns, *chosen runs the subcommand given (with `actions`, which must outlive it). Command-line
// mistakes throw CLI::ParseError from app.parse().
void add_commands(CLI::App& app, const CommandActions& actions, std::function<int()>* chosen);

// The one line printed for a command-line mistake: "error: <CLI11's message> (perifrac --help ...)",
// control characters of quoted arguments shown as '?'.
std::string command_line_error(const CLI::ParseError& e);

// The line for a first argument that names no command of `app` (not an option): "unknown
// command" with the commands allowed; empty where it names one, or is an option.
std::string unknown_command_error(const CLI::App& app, const std::string& first);

}  // namespace pd
