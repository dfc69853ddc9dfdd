// `perifrac run SCENE`: load, set up, simulate frame by frame, write outputs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pd {

struct RunOptions {
  std::string scene;
  std::string backend = "auto";
  int64_t frames = -1;           // -1: the scene's
  int64_t steps_per_frame = -1;  // -1: the scene's
  std::string out;               // empty: out/<scene name>
  double scale = 1.0;
  bool scale_given = false;  // --scale was on the command line (a resumed run refuses another)
  bool checkpoint_every_given = false, checkpoint_minutes_given = false;  // (else a resume keeps the run's)
  bool allow_unstable_dt = false;
  // Every particle finds its partners from its listed family, box-grid bodies too (no lattice
  // families): the families a run over several ranks uses, so one rank gives its bits.
  bool explicit_families = false;
  int blend_frames = 0;  // fragment split blending (host/fragments/smoothing.h); 0: off
  // Checkpoints (host/app/checkpoint.h) after every N frames and every M minutes of wall time
  // (0: off), and on SIGINT/SIGTERM. `resume`: an output folder to continue from its checkpoint.
  int64_t checkpoint_every = 0;
  double checkpoint_minutes = 10;
  std::string resume;
  // A folder holding another run is refused unless `overwrite`, which removes that run's files
  // (host/app/run_folder.h).
  bool overwrite = false;
  std::vector<std::string> overrides;  // --set KEY=VALUE, applied to the scene file
};

// Exit codes shared by the commands.
enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 2,          // bad scene, option or input file
  kExitBlowUp = 3,         // numerical blow-up detected
  kExitRuntime = 4,        // device or I/O failure
  kExitInterrupted = 130,  // SIGINT/SIGTERM: stopped after writing a checkpoint
};

int run_command(const RunOptions& options);

}  // namespace pd
