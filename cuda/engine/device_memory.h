// The engine's allocator: arrays in the backend's memory (DeviceArray), with the bytes they
// hold counted, so the engine can report its footprint (Engine::memory_bytes).
#pragma once

#include <cstddef>
#include <vector>

#include "cuda/device_array.h"

namespace pd {

template <class Exec>
class DeviceMemory {
 public:
  explicit DeviceMemory(Exec* exec) : exec_(exec) {}

  template <class T>
  DeviceArray<T, Exec> make(size_t n) {
    bytes_ += n * sizeof(T);
    return DeviceArray<T, Exec>(exec_, n);
  }
  template <class T>
  DeviceArray<T, Exec> make_zeroed(size_t n) {
    auto a = make<T>(n);
    a.zero();
    return a;
  }
  template <class T>
  DeviceArray<T, Exec> make_from(const std::vector<T>& host) {
    auto a = make<T>(host.size());
    a.upload(host);
    return a;
  }
  // Frees an array and takes its bytes off the count.
  template <class T>
  void drop(DeviceArray<T, Exec>& a) {
    bytes_ -= a.bytes();
    a = DeviceArray<T, Exec>();
  }
  size_t bytes() const { return bytes_; }
  Exec& exec() const { return *exec_; }

 private:
  Exec* exec_;
  size_t bytes_ = 0;
};

}  // namespace pd
