// The CPU renderer: the shared pixel kernel run by OpenMP loops.
#include <omp.h>

#include "cuda/exec_cpu.h"
#include "render/renderer_impl.h"

namespace pd {

std::unique_ptr<Renderer> make_cpu_renderer() {
  return std::make_unique<RendererImpl<CpuExec>>("CPU (" + std::to_string(omp_get_max_threads()) +
                                                 " threads)");
}

}  // namespace pd
