// A plain view of an array (Warp style): a raw pointer and its length, passed by value into
// kernel bodies. Indexing is checked when PERIFRAC_BOUNDS_CHECKS is defined (the cpu-asan and
// cuda-debug presets): an index outside [0, size) prints the index, the size and the place, and
// stops the run (abort on the CPU, a trap on the GPU). Without it, indexing is the raw pointer's.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "cuda/pd_common.h"

namespace pd {

template <class T>
struct ArrayView {
  T* ptr = nullptr;
  int64_t size = 0;

  ArrayView() = default;
  PD_HD ArrayView(T* p, int64_t n) : ptr(p), size(n) {}
  // A view of const T from a view of T.
  template <class U, class = std::enable_if_t<std::is_same_v<const U, T> && !std::is_same_v<U, T>>>
  PD_HD ArrayView(ArrayView<U> o) : ptr(o.ptr), size(o.size) {}

  PD_HD T& operator[](int64_t i) const {
    PD_CHECK_INDEX(i, size);
    return ptr[i];
  }
  PD_HD T* data() const { return ptr; }
  // Entries [first, first + count) as a view of their own (checked: they must lie in this one).
  PD_HD ArrayView sub(int64_t first, int64_t count) const {
    if (count > 0) {
      PD_CHECK_INDEX(first, size);
      PD_CHECK_INDEX(first + count - 1, size);
    }
    return {ptr + first, count};
  }
  PD_HD explicit operator bool() const { return ptr != nullptr; }
};

// The view of a host vector (tests and host-side readers of families).
template <class T>
ArrayView<T> view_of(std::vector<T>& v) {
  return {v.data(), int64_t(v.size())};
}
template <class T>
ArrayView<const T> view_of(const std::vector<T>& v) {
  return {v.data(), int64_t(v.size())};
}

}  // namespace pd
