// An owning array in a backend's memory (host memory for CpuExec, device memory for CudaExec).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "cuda/array_view.h"

namespace pd {

template <class T, class Exec>
class DeviceArray {
 public:
  DeviceArray() = default;
  DeviceArray(Exec* exec, size_t n) : exec_(exec), size_(n) {
    data_ = static_cast<T*>(exec_->allocate(n * sizeof(T)));
  }
  ~DeviceArray() {
    if (data_) exec_->release(data_);
  }
  DeviceArray(DeviceArray&& o) noexcept { swap(o); }
  DeviceArray& operator=(DeviceArray&& o) noexcept {
    swap(o);
    return *this;
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;

  T* data() const { return data_; }
  size_t size() const { return size_; }
  size_t bytes() const { return size_ * sizeof(T); }

  // Copies to and from host vectors; an empty array copies nothing (its data is null).
  void upload(const std::vector<T>& host) {
    if (size_ > 0) exec_->upload(data_, host.data(), bytes());
  }
  void download(std::vector<T>& host) const {
    host.resize(size_);
    if (size_ > 0) exec_->download(host.data(), data_, bytes());
  }
  void zero() {
    if (size_ > 0) exec_->fill_bytes(data_, 0, bytes());
  }

 private:
  void swap(DeviceArray& o) {
    std::swap(exec_, o.exec_);
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
  }
  Exec* exec_ = nullptr;
  T* data_ = nullptr;
  size_t size_ = 0;
};

// The view of a backend array, for kernels.
template <class T, class Exec>
ArrayView<T> view_of(const DeviceArray<T, Exec>& a) {
  return {a.data(), int64_t(a.size())};
}

}  // namespace pd
