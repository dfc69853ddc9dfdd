#include "host/geometry/particle_order.h"

#include <algorithm>
#include <stdexcept>

#include "host/geometry/curve_order.h"

namespace pd {
namespace {

// A CSR list (offset, values) rearranged into the new particle order; `renumber` maps each value.
template <class T, class Renumber>
void reorder_csr(std::vector<int64_t>& offset, std::vector<T>& values, const std::vector<int32_t>& order,
                 Renumber renumber) {
  std::vector<int64_t> new_offset{0};
  std::vector<T> new_values;
  new_offset.reserve(order.size() + 1);
  new_values.reserve(values.size());
  for (int32_t old : order) {
    for (int64_t k = offset[size_t(old)]; k < offset[size_t(old) + 1]; ++k)
      new_values.push_back(renumber(values[size_t(k)]));
    new_offset.push_back(int64_t(new_values.size()));
  }
  offset = std::move(new_offset);
  values = std::move(new_values);
}

}  // namespace

void reorder_particles(ParticleGeometry& g, const std::vector<int32_t>& order) {
  if (g.kind != ElementKind::tet) throw std::logic_error("reorder_particles: tets only");
  if (order.size() != g.size()) throw std::logic_error("reorder_particles: the order is not a permutation");
  std::vector<int32_t> new_index(order.size(), -1);
  for (size_t k = 0; k < order.size(); ++k) new_index[size_t(order[k])] = int32_t(k);
  const auto renumber = [&](int32_t old) { return old >= 0 ? new_index[size_t(old)] : old; };

  g.position = permuted(g.position, order);
  g.volume = permuted(g.volume, order);
  if (!g.mass.empty()) g.mass = permuted(g.mass, order);
  if (!g.lambda.empty()) g.lambda = permuted(g.lambda, order);
  // Each list stays sorted: the lists were sorted by old index, and are re-sorted by new. (A
  // geometry without its adjacency yet, as tet_particles orders it, has none to move.)
  if (g.adjacency.size() == order.size()) {
    reorder_csr(g.adjacency.offset, g.adjacency.neighbor, order, renumber);
    for (size_t i = 0; i < g.adjacency.size(); ++i)
      std::sort(g.adjacency.neighbor.begin() + g.adjacency.offset[i],
                g.adjacency.neighbor.begin() + g.adjacency.offset[i + 1]);
  }
  g.tets.tets = permuted(g.tets.tets, order);
  g.tets.neighbors = permuted(g.tets.neighbors, order);
  for (auto& across : g.tets.neighbors)
    for (int32_t& t : across) t = renumber(t);
}

}  // namespace pd
