// Kernel 2, `collection`: put each particle into its spatial-hash bin. The engine sorts
// (bin, particle) pairs between the two bodies below, which keeps runs deterministic
// where atomic bin insertion would not be.
#pragma once

#include "cuda/views.h"

namespace pd {

PD_HD inline void hash_particle(int32_t i, Vec3 x, HashView h) {
  h.key[i] = cell_bin(cell_of(x, h.inv_cell), h.bins);
  h.sorted[i] = i;
}

// Before hashing: bin b empty.
PD_HD inline void reset_bin(uint32_t b, HashView h) {
  h.bin_start[b] = -1;
  h.bin_end[b] = -1;
}

// After sorting: record where each bin's run of entries starts and ends.
PD_HD inline void mark_bin_bounds(int32_t s, int32_t n, HashView h) {
  const uint32_t k = h.key[s];
  if (s == 0 || h.key[s - 1] != k) h.bin_start[k] = s;
  if (s == n - 1 || h.key[s + 1] != k) h.bin_end[k] = s + 1;
}

// Calls visit(s) for every sorted entry s in bin b (of one cell or several).
template <class Visit>
PD_HD inline void for_each_entry_in_bin(uint32_t b, HashView h, Visit visit) {
  const int32_t begin = h.bin_start[b];
  if (begin < 0) return;
  const int32_t end = h.bin_end[b];
  for (int32_t s = begin; s < end; ++s) visit(s);
}

// Visit every particle hashed into cell `nc`. `pos(j)` must return the same position that
// was hashed, so the cell comparison is exact.
template <class PositionFn, class Visit>
PD_HD inline void for_each_in_cell(Cell nc, HashView h, PositionFn pos, Visit visit) {
  for_each_entry_in_bin(cell_bin(nc, h.bins), h, [&](int32_t s) {
    const int32_t j = h.sorted[s];
    if (same_cell(cell_of(pos(j), h.inv_cell), nc)) visit(j);
  });
}

// Every particle within one cell side of `x`: the 27 cells around x's cell.
template <class PositionFn, class Visit>
PD_HD inline void for_each_nearby(Vec3 x, HashView h, PositionFn pos, Visit visit) {
  const Cell c = cell_of(x, h.inv_cell);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) for_each_in_cell({c.x + dx, c.y + dy, c.z + dz}, h, pos, visit);
}

// The 8 cells that hold every particle within half a cell side of `x` (and some farther): on
// each axis x's cell and the neighbour on the side of x's half of it.
template <class CellFn>
PD_HD inline void for_each_half_cell_neighbourhood(Vec3 x, HashView h, CellFn cell_fn) {
  const Cell c = cell_of(x, h.inv_cell);
  auto low = [&](real v, int32_t cell) { return v * h.inv_cell - real(cell) < real(0.5) ? cell - 1 : cell; };
  const Cell lo{low(x.x, c.x), low(x.y, c.y), low(x.z, c.z)};
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) cell_fn(Cell{lo.x + dx, lo.y + dy, lo.z + dz});
}

// Every particle within half a cell side of `x` (and some farther), 8 cells instead of 27, read
// from the sorted records (HashView::record): visit(s, record) once per sorted entry s of the
// bins of those cells, each bin's run contiguously. Entries of other cells that share a bin are
// visited too (no per-entry cell test: the caller's distance test rejects them, since they lie
// farther than half a cell side); a bin two of the cells share is read once.
template <class Visit>
PD_HD inline void for_each_record_within_half_cell(Vec3 x, HashView h, Visit visit) {
  uint32_t seen[8];
  int32_t bins_seen = 0;
  for_each_half_cell_neighbourhood(x, h, [&](Cell nc) {
    const uint32_t b = cell_bin(nc, h.bins);
    for (int32_t k = 0; k < bins_seen; ++k)
      if (seen[k] == b) return;
    seen[bins_seen++] = b;
    for_each_entry_in_bin(b, h, [&](int32_t s) { visit(s, h.record[s]); });
  });
}

}  // namespace pd
