#include "host/fragments/align.h"

#include <stdexcept>
#include <string>

namespace pd {

void align_fragments(const Components& c, const std::vector<Vec3>& rest, const std::vector<Vec3>& current,
                     const std::vector<real>& mass, std::vector<Fragment>& out) {
  const size_t n = c.id.size();
  if (rest.size() != n || current.size() != n || mass.size() != n)
    throw std::invalid_argument("align_fragments: per-particle arrays differ in length from the components");
  // Checked here: fit_rigid's own check would throw inside the parallel loop.
  for (size_t i = 0; i < n; ++i)
    if (!(mass[i] > 0))
      throw std::invalid_argument("align_fragments: particle " + std::to_string(i) + " has mass <= 0");
  out.resize(c.count());
  // Components are independent; sizes vary wildly (one body and many single particles), so the
  // loop hands them out dynamically.
  const int64_t count = int64_t(c.count());
#pragma omp parallel for schedule(dynamic, 64)
  for (int64_t k = 0; k < count; ++k) {
    Fragment& f = out[size_t(k)];
    f.id = c.component_id(size_t(k));
    f.particles = c.size(size_t(k));
    f.fit = fit_rigid(rest.data(), current.data(), mass.data(), c.members.data() + c.start[size_t(k)],
                      size_t(f.particles));
    f.rotation = f.fit.rotation;
    f.translation = f.fit.translation;
    f.blend = 0;
  }
}

}  // namespace pd
