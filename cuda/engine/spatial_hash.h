// The spatial hash's buffers (HashView, cuda/views.h): built over reference positions for the
// family search, and over current positions for the contact lists.
#pragma once

#include <cstdint>

#include "cuda/engine/device_memory.h"
#include "cuda/views.h"

namespace pd {

// Bins for n particles: the next power of two at or above 2n (at least 1024, at most 2^30).
inline uint32_t hash_bins_for(int64_t n) {
  uint32_t bins = 1024;
  while (bins < 2 * n && bins < (1u << 30)) bins <<= 1;
  return bins;
}

template <class Exec>
struct SpatialHash {
  uint32_t bins = 0;
  real inv_cell = 0;
  DeviceArray<uint32_t, Exec> key, key_sorted;
  DeviceArray<int32_t, Exec> ids, ids_sorted, bin_start, bin_end;
  DeviceArray<Vec4, Exec> record;  // contact lists only: sorted records for the build

  // Buffers for n particles in cells of side `cell`.
  void allocate(DeviceMemory<Exec>& mem, int32_t n, real cell) {
    bins = hash_bins_for(n);
    inv_cell = real(1) / cell;
    key = mem.template make<uint32_t>(size_t(n));
    key_sorted = mem.template make<uint32_t>(size_t(n));
    ids = mem.template make<int32_t>(size_t(n));
    ids_sorted = mem.template make<int32_t>(size_t(n));
    bin_start = mem.template make<int32_t>(bins);
    bin_end = mem.template make<int32_t>(bins);
  }

  void release(DeviceMemory<Exec>& mem) {
    mem.drop(key);
    mem.drop(key_sorted);
    mem.drop(ids);
    mem.drop(ids_sorted);
    mem.drop(bin_start);
    mem.drop(bin_end);
    mem.drop(record);
    bins = 0;
  }

  // The unsorted (keys and ids as computed) or the sorted side.
  HashView view(bool sorted) const {
    HashView h;
    h.bins = bins;
    h.inv_cell = inv_cell;
    h.key = view_of(sorted ? key_sorted : key);
    h.sorted = view_of(sorted ? ids_sorted : ids);
    h.bin_start = view_of(bin_start);
    h.bin_end = view_of(bin_end);
    if (sorted) h.record = view_of(record);
    return h;
  }
};

}  // namespace pd
