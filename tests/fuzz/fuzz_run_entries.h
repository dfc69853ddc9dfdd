// The entries of the fuzz targets of a run's own inputs: the checkpoint reader and the command-line
// parser (tests/fuzz/fuzz_checkpoint.cpp, fuzz_command_line.cpp; their regressions run in
// tests/host/fuzz/test_fuzz_regressions.cpp). Each holds its parser to the contract of every input,
// as fuzz_entries.h does: a valid result or a clean error; a broken contract throws
// ContractViolation.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "host/app/checkpoint.h"
#include "host/cli/command_line.h"
#include "host/io/atomic_file.h"
#include "host/io/checksum.h"
#include "tests/fuzz/fuzz_entries.h"

namespace pd::fuzz {

// ---- Checkpoints -----------------------------------------------------------------------------

// The bytes with their trailing checksum made right (the last 8 bytes hold the FNV-1a of the rest),
// so that fuzzing gets past the checksum into the records.
inline std::string with_checksum(std::string bytes) {
  if (bytes.size() < 8) return bytes;
  const uint64_t hash = fnv1a(std::string_view(bytes).substr(0, bytes.size() - 8));
  std::memcpy(&bytes[bytes.size() - 8], &hash, 8);
  return bytes;
}

// Reads `bytes` (checksum fixed) as a checkpoint file. Returns "" for a checkpoint whose values are
// in the ranges a resume relies on, else the clean error: "cannot read '<path>': <reason>", one line.
inline std::string checkpoint_entry(const std::string& bytes) {
  const std::string path = (std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp")) +
                           "/perifrac_fuzz_" + std::to_string(::getpid()) + ".pck";
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    require(f != nullptr, "cannot write the fuzz input file " + path);
    const std::string fixed = with_checksum(bytes);
    std::fwrite(fixed.data(), 1, fixed.size(), f);
    std::fclose(f);
  }
  try {
    const RunCheckpoint c = read_checkpoint(path);
    std::remove(path.c_str());
    require(c.steps_per_frame >= 1 && c.steps_per_frame <= kMaxStepsPerFrame, "steps_per_frame");
    require(c.frames >= 0 && c.frames <= kMaxFrames && c.frame >= 0 && c.frame <= c.frames, "frames");
    require(
        c.engine.step >= c.frame * c.steps_per_frame && c.engine.step <= (c.frame + 1) * c.steps_per_frame,
        "step");
    require(std::isfinite(c.scale) && c.scale >= 0 && std::isfinite(c.engine.time), "scale, time");
    require(std::isfinite(c.checkpoint_minutes) && c.checkpoint_minutes >= 0, "checkpoint_minutes");
    for (const auto& e : c.series) require(std::isfinite(e.time), "series time");
    for (const auto& k : c.smoother.previous) require(k.particles >= 0 && k.age >= -1, "corrections");
    return "";
  } catch (const IoError& e) {
    std::remove(path.c_str());
    const std::string message = e.what(), head = "cannot read '" + path + "': ";
    require(message.compare(0, head.size(), head) == 0, "the error does not name the file: " + message);
    for (char ch : message)
      require(static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7f,
              "the error is not one printable line: " + message);
    return message;
  }
}

// ---- The command line ------------------------------------------------------------------------

// The bytes as a command line: arguments separated by NUL bytes (at most 64), after "perifrac".
inline std::vector<std::string> arguments_of(const std::string& bytes) {
  std::vector<std::string> args{"perifrac"};
  size_t start = 0;
  while (start <= bytes.size() && args.size() < 65) {
    const size_t end = std::min(bytes.find('\0', start), bytes.size());
    args.push_back(bytes.substr(start, end - start));
    start = end + 1;
  }
  return args;
}

// Parses `bytes` as a command line with actions that only record what they were given. Returns ""
// when the line parses into one subcommand (whose options must then be in their documented
// ranges), else CLI11's error message, which must be one line.
inline std::string command_line_entry(const std::string& bytes) {
  const std::vector<std::string> args = arguments_of(bytes);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  CommandActions actions;
  const auto check_run = [](const RunOptions& o) {
    require(o.frames == -1 || (o.frames >= 0 && o.frames <= kMaxFrames), "--frames");
    require(o.steps_per_frame == -1 || (o.steps_per_frame >= 1 && o.steps_per_frame <= kMaxStepsPerFrame),
            "--steps-per-frame");
    require(o.checkpoint_every >= 0 && o.checkpoint_minutes >= 0, "checkpoint options");
    require(!(o.overwrite && !o.resume.empty()), "--overwrite with --resume");
    return 0;
  };
  actions.run = check_run;
  actions.bench = [](const BenchOptions&) { return 0; };
  actions.bench_render = [](const RenderBenchOptions& o) {
    require(o.width >= 16 && o.height >= 16 && o.spp >= 1, "bench-render image options");
    return 0;
  };
  actions.bench_geometry = [](const GeometryBenchOptions&) { return 0; };
  actions.shapes = [](const ShapeExportOptions&) { return 0; };
  actions.bench_fragments = [](const FragmentsBenchOptions&) { return 0; };
  actions.profile = [](const ProfileOptions&) { return 0; };
  actions.validate = [](const ValidateOptions&) { return 0; };
  actions.render = [](const RenderOptions& o) {
    require(o.width >= 16 && o.width <= 16384 && o.height >= 16 && o.height <= 16384, "render size");
    require(o.spp >= 1 && o.spp <= 1024, "render spp");
    return 0;
  };
  actions.compare = [](const CompareOptions&) { return 0; };
  actions.info = [] { return 0; };
  CLI::App app{"perifrac"};
  std::function<int()> chosen;
  add_commands(app, actions, &chosen);
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::CallForHelp&) {
    return "(help)";
  } catch (const CLI::CallForAllHelp&) {
    return "(help)";
  } catch (const CLI::CallForVersion&) {
    return "(version)";
  } catch (const CLI::ParseError& e) {
    const std::string line = command_line_error(e);
    require(line.rfind("error: ", 0) == 0, "the error does not start with 'error: ': " + line);
    for (char ch : line)
      require(static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7f,
              "the error is not one printable line: " + line);
    return line;
  }
  require(static_cast<bool>(chosen), "a command line parsed without choosing a subcommand");
  chosen();  // the options' checks above
  return "";
}

}  // namespace pd::fuzz
