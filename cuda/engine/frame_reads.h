// A frame read back beside the steps that follow it (Engine::read_frame, issue 27): the state
// table's frame fields and the bonds' changed bits are copied into host memory of a slot
// (page-locked on the GPU, on a stream of their own), and the reader's finish() waits for them and
// unpacks them into a ParticleState and a BondChanges, on the reader's thread. A few slots are
// reused from frame to frame (up to 1 GiB of them); while all are out (the readers behind), or
// where page-locked memory is refused, a frame is read at once.
#pragma once

#include <algorithm>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "cuda/engine/engine.h"
#include "cuda/read_back.h"

namespace pd {

template <class Exec>
class FrameReadSlots {
 public:
  // Slots at most, and the page-locked memory they may hold together, 1 GiB unless given (at
  // least one slot is allowed whatever its size: a frame is read into host memory of its size
  // either way).
  static constexpr int kMostSlots = 4;
  explicit FrameReadSlots(size_t most_bytes = size_t(1) << 30) : most_bytes_(most_bytes) {}

  struct Slot {
    void* host = nullptr;
    size_t bytes = 0;
    typename Exec::ReadEvent done;
    ~Slot() { release(); }
    void release() {
      if (!host) return;
      done.wait();  // (copies may still be landing in it when its reader was dropped unfinished)
      Exec::release_host(host);
      host = nullptr;
      bytes = 0;
    }
  };

  // A slot of at least `bytes`, or null when as many are out as kMostSlots and the bytes allow,
  // or when page-locked memory could not be had (then never again: the frames are read at once).
  std::unique_ptr<Slot> take(Exec& exec, size_t bytes) {
    std::unique_ptr<Slot> slot;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      const int most = int(std::clamp<size_t>(most_bytes_ / std::max<size_t>(bytes, 1), 1, kMostSlots));
      if (refused_ || out_ >= most) return nullptr;
      ++out_;
      if (!free_.empty()) {
        slot = std::move(free_.back());
        free_.pop_back();
      }
    }
    if (!slot) slot = std::make_unique<Slot>();
    if (slot->bytes < bytes) {
      slot->release();
      try {
        slot->host = exec.allocate_host(bytes);
        slot->bytes = bytes;
      } catch (const std::exception&) {
        const std::lock_guard<std::mutex> lock(mutex_);
        refused_ = true;
        --out_;
        return nullptr;
      }
    }
    return slot;
  }

  void give_back(std::unique_ptr<Slot> slot) {
    const std::lock_guard<std::mutex> lock(mutex_);
    --out_;
    free_.push_back(std::move(slot));
  }

 private:
  size_t most_bytes_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Slot>> free_;
  int out_ = 0;           // slots taken and not given back
  bool refused_ = false;  // page-locked memory refused once
};

// Where each part of a frame lies in its slot.
struct FrameLayout {
  std::vector<FrameField> fields;  // the state's, as stored
  std::vector<size_t> offset;      // each field's place in the slot
  size_t flipped_offset = 0, flipped_words = 0;
  bool has_changes = false;
  BondChanges whole;  // the changes when they are the bonds whole (read at once)
  size_t bytes = 0;
};

// The layout of `fields`, and of `flipped_words` words of changed bits when has_changes.
inline FrameLayout frame_layout(const std::vector<FrameField>& fields, bool has_changes,
                                size_t flipped_words) {
  constexpr size_t kAlign = 64;
  FrameLayout l;
  l.fields = fields;
  for (const FrameField& f : fields) {
    l.offset.push_back(l.bytes);
    l.bytes += (f.count * f.bytes + kAlign - 1) / kAlign * kAlign;
  }
  l.has_changes = has_changes;
  l.flipped_words = flipped_words;
  l.flipped_offset = l.bytes;
  l.bytes += flipped_words * sizeof(uint32_t);
  return l;
}

template <class Exec>
class SlotFrameRead final : public FrameRead {
 public:
  using Slots = FrameReadSlots<Exec>;
  SlotFrameRead(std::shared_ptr<Slots> slots, std::unique_ptr<typename Slots::Slot> slot, FrameLayout layout)
      : slots_(std::move(slots)), slot_(std::move(slot)), layout_(std::move(layout)) {}
  ~SlotFrameRead() override { slots_->give_back(std::move(slot_)); }
  SlotFrameRead(const SlotFrameRead&) = delete;
  SlotFrameRead& operator=(const SlotFrameRead&) = delete;

  void finish(ParticleState& state, BondChanges& changes) override {
    slot_->done.wait();
    const char* host = static_cast<const char*>(slot_->host);
    size_t k = 0;
    for_each_frame_member(state, [&](auto& member, auto is_xyz) {
      const FrameField& f = layout_.fields[k];
      const char* from = host + layout_.offset[k++];
      member.resize(f.count);
      if constexpr (decltype(is_xyz)::value) {
        const Vec4* v = reinterpret_cast<const Vec4*>(from);
        for (size_t i = 0; i < f.count; ++i) member[i] = pd::xyz(v[i]);
      } else {
        if (f.count > 0) std::memcpy(member.data(), from, f.count * f.bytes);
      }
    });
    if (!layout_.has_changes) return;
    if (layout_.whole.whole) {
      changes = std::move(layout_.whole);
      return;
    }
    changes.whole = false;
    changes.flipped.resize(layout_.flipped_words);
    if (layout_.flipped_words > 0)
      std::memcpy(changes.flipped.data(), host + layout_.flipped_offset,
                  layout_.flipped_words * sizeof(uint32_t));
  }

 private:
  std::shared_ptr<Slots> slots_;
  std::unique_ptr<typename Slots::Slot> slot_;
  FrameLayout layout_;
};

}  // namespace pd
