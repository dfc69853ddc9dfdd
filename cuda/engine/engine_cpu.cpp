// The CPU-reference engine: the shared kernel bodies run by OpenMP loops.
#include <omp.h>

#include <fstream>

#include "cuda/engine/engine_impl.h"
#include "cuda/exec_cpu.h"
#include "cuda/parallel/partitioned_engine.h"

namespace pd {

namespace {
std::string cpu_description() {
  std::ifstream info("/proc/cpuinfo");
  std::string line, model = "CPU";
  while (std::getline(info, line)) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  return model + " (" + std::to_string(omp_get_max_threads()) + " threads)";
}
}  // namespace

std::unique_ptr<Engine> make_cpu_engine(const SimulationInput& in) {
  if (auto world = world_comm()) return make_partitioned_engine<CpuExec>(in, world, cpu_description());
  return make_local_cpu_engine(in);
}

std::unique_ptr<Engine> make_local_cpu_engine(const SimulationInput& in) {
  return std::make_unique<EngineImpl<CpuExec>>(in, cpu_description());
}

}  // namespace pd
