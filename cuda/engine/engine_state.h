// The engine's state arrays in the backend's memory: one DeviceArray per field of the state
// table (cuda/state_fields.h), allocated for the fields a run needs, uploaded from the particle
// set, paired with the snapshot's vectors for save and restore, and seen by the kernels through
// ParticlesView and BondsView.
#pragma once

#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "cuda/engine/device_memory.h"
#include "cuda/engine/engine.h"
#include "cuda/views.h"

namespace pd {

// Downloads one field for a frame into `out` (its memory kept when its size holds): whole, or the
// xyz part of each element, through `whole`, kept likewise.
template <FieldFrame kFrame, class T, class Exec, class Out>
void read_frame_field(const DeviceArray<T, Exec>& array, std::vector<Out>& out, std::vector<Vec4>& whole) {
  if constexpr (kFrame == kFrameXyz) {
    static_assert(std::is_same_v<T, Vec4>, "an xyz frame field is stored as Vec4");
    array.download(whole);
    out.resize(whole.size());
    for (size_t i = 0; i < whole.size(); ++i) out[i] = xyz(whole[i]);
  } else {
    array.download(out);
  }
}

// `a` with room for n entries, its entries kept and the new ones zero.
template <class T, class Exec>
void grow(DeviceMemory<Exec>& mem, DeviceArray<T, Exec>& a, size_t n) {
  auto bigger = mem.template make_zeroed<T>(n);
  const ArrayView<const T> from = view_of(a);
  const ArrayView<T> to = view_of(bigger);
  mem.exec().parallel_for("state/grow", from.size, [=] PD_HD(int64_t i) { to[i] = from[i]; });
  mem.drop(a);
  a = std::move(bigger);
}

// Every entry of `a` set to `value`, on the backend.
template <class T, class Exec>
void fill(DeviceMemory<Exec>& mem, DeviceArray<T, Exec>& a, T value) {
  const ArrayView<T> to = view_of(a);
  mem.exec().parallel_for("state/fill", to.size, [=] PD_HD(int64_t i) { to[i] = value; });
}

template <class Exec>
struct EngineState {
  int32_t n = 0;
#define PD_STATE_ARRAY(name, Type, ...) DeviceArray<std::remove_const_t<Type>, Exec> name;
  PD_STATE_FIELDS(PD_STATE_ARRAY)
#undef PD_STATE_ARRAY

  // Allocates, zeroed, every field of this length that a run with `needs` has and that is not
  // allocated yet, `entries` entries each.
  void allocate(DeviceMemory<Exec>& mem, FieldLength wanted, size_t entries, FieldNeeds needs) {
#define PD_STATE_ALLOCATE(name, Type, length, when, ...)   \
  if (length == wanted && needs(when) && name.size() == 0) \
    name = mem.template make_zeroed<std::remove_const_t<Type>>(entries);
    PD_STATE_FIELDS(PD_STATE_ALLOCATE)
#undef PD_STATE_ALLOCATE
  }

  // The per-particle fields from the particle set: every one allocated (zeroed), then those the
  // scene gives filled in. Derived inputs: rest holds (X, V), disp starts at (0, tau_i).
  void upload(DeviceMemory<Exec>& mem, const ParticleSet& ps, FieldNeeds needs) {
    n = int32_t(ps.size());
    allocate(mem, kParticles, ps.size(), needs);
    const size_t particle_count = ps.size();
    std::vector<Vec4> rest4(particle_count), disp4(particle_count);
    std::vector<real> inv(particle_count);
    for (size_t i = 0; i < particle_count; ++i) {
      rest4[i] = with_w(ps.rest[i], ps.volume[i]);
      disp4[i] = {0, 0, 0, ps.strain_limit0[i]};
      inv[i] = real(1) / ps.mass[i];
    }
    rest.upload(rest4);
    disp.upload(disp4);
    vel.upload(ps.velocity);
    inv_mass.upload(inv);
    material.upload(ps.material);
    body.upload(ps.body);
    flags.upload(ps.flags);
    if (ps.anchor.size() == ps.size()) anchor.upload(ps.anchor);
    strain_limit0.upload(ps.strain_limit0);
  }

  // Room for `capacity` particles in every per-particle field it has (kept entries, new ones
  // zero): a partitioned rank's contact ghosts come and go after its own and its bond ghosts.
  void reserve_particles(DeviceMemory<Exec>& mem, size_t capacity) {
#define PD_STATE_GROW(name, Type, length, when, ...) \
  if (length == kParticles && name.size() > 0 && name.size() < capacity) grow(mem, name, capacity);
    PD_STATE_FIELDS(PD_STATE_GROW)
#undef PD_STATE_GROW
  }

  ParticlesView particles() const {
    ParticlesView p;
    p.n = n;
#define PD_STATE_VIEW(name, ...) p.name = view_of(name);
    PD_PARTICLE_FIELDS(PD_STATE_VIEW)
#undef PD_STATE_VIEW
    return p;
  }

  // The bond fields; the lattice part is the family builder's (LatticeState::view).
  BondsView bonds() const {
    BondsView b;
    b.n = n;
#define PD_STATE_BOND_VIEW(name, ...) b.name = view_of(name);
    PD_BOND_FIELDS(PD_STATE_BOND_VIEW)
#undef PD_STATE_BOND_VIEW
    return b;
  }

  // f(name, array, snapshot vector) for every saved field (save, restore).
  template <class Snapshot, class F>
  void for_each_saved(Snapshot& s, F f) {
#define PD_STATE_SAVED(name, Type, length, when, saved, ...) PD_IF_SAVED(saved, f(#name, name, s.name);)
    PD_STATE_FIELDS(PD_STATE_SAVED)
#undef PD_STATE_SAVED
  }

  // The fields with a frame role, whole or their xyz part (ParticleState), into `out`'s memory.
  void read_frame(ParticleState& out) const {
#define PD_STATE_FRAME(name, Type, length, when, saved, halo, frame) \
  PD_IF_FRAME(frame, read_frame_field<frame>(name, out.name, frame_whole_);)
    PD_PARTICLE_FIELDS(PD_STATE_FRAME)
#undef PD_STATE_FRAME
  }

  // The same fields' memory as stored, in the table's order (Engine::read_frame's copies).
  std::vector<FrameField> frame_fields() const {
    std::vector<FrameField> fields;
#define PD_STATE_FRAME_FIELD(name, Type, length, when, saved, halo, frame) \
  PD_IF_FRAME(frame, fields.push_back({name.data(), name.size(), sizeof(Type)});)
    PD_PARTICLE_FIELDS(PD_STATE_FRAME_FIELD)
#undef PD_STATE_FRAME_FIELD
    return fields;
  }

  void save(EngineSnapshot& out) {
    for_each_saved(out, [](const char*, auto& array, auto& host) { array.download(host); });
  }
  // Throws std::invalid_argument, changing nothing, when a snapshot vector's size is not the
  // array's (another scene or scale); otherwise uploads every saved field.
  // Each saved bond slot must hold the partner this engine's families hold there, broken or not
  // (~partner): a snapshot of other bonds, or a crafted one, could make the kernels read outside the
  // particles.
  void check_sizes(const EngineSnapshot& in) {
    for_each_saved(in, [](const char* what, auto& array, const auto& host) {
      if (host.size() != array.size())
        throw std::invalid_argument(std::string("snapshot ") + what + " has " + std::to_string(host.size()) +
                                    " entries, the engine " + std::to_string(array.size()));
    });
    std::vector<int32_t> built;
    neighbor.download(built);
    const auto partner = [](int32_t slot) { return slot < 0 ? ~slot : slot; };
    for (size_t k = 0; k < built.size(); ++k)
      if (partner(in.neighbor[k]) != partner(built[k]))
        throw std::invalid_argument("snapshot neighbor slot " + std::to_string(k) + " holds partner " +
                                    std::to_string(partner(in.neighbor[k])) + ", the engine's families " +
                                    std::to_string(partner(built[k])));
  }
  void upload_saved(const EngineSnapshot& in) {
    for_each_saved(in, [](const char*, auto& array, const auto& host) { array.upload(host); });
  }
  // The saved per-particle fields of `in` alone, their sizes checked (std::invalid_argument,
  // nothing uploaded); the bond slots' fields are left as they are.
  void upload_saved_particles(const EngineSnapshot& in) {
    const auto check = [](const char* what, const auto& array, const auto& host) {
      if (host.size() != array.size())
        throw std::invalid_argument(std::string("snapshot ") + what + " has " + std::to_string(host.size()) +
                                    " entries, the engine " + std::to_string(array.size()));
    };
#define PD_STATE_CHECK_PARTICLE(name, Type, length, when, saved, ...) \
  PD_IF_SAVED(saved, check(#name, name, in.name);)
    PD_PARTICLE_FIELDS(PD_STATE_CHECK_PARTICLE)
#undef PD_STATE_CHECK_PARTICLE
#define PD_STATE_UPLOAD_PARTICLE(name, Type, length, when, saved, ...) \
  PD_IF_SAVED(saved, name.upload(in.name);)
    PD_PARTICLE_FIELDS(PD_STATE_UPLOAD_PARTICLE)
#undef PD_STATE_UPLOAD_PARTICLE
  }

 private:
  mutable std::vector<Vec4> frame_whole_;  // read_frame's download of an xyz field, kept for the next
};

}  // namespace pd
