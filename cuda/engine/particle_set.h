// Host-side particle data before a run: the input every engine starts from.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "cuda/engine/body_solids.h"
#include "cuda/engine/cut_triangle.h"
#include "cuda/engine/motion.h"
#include "cuda/views.h"

namespace pd {

struct ParticleSet {
  std::vector<Vec3> rest;           // reference positions [m]
  std::vector<Vec3> velocity;       // initial velocities [m/s]
  std::vector<real> volume;         // [m^3]
  std::vector<real> mass;           // [kg]
  std::vector<real> strain_limit0;  // scattered base strain limit per particle
  std::vector<uint16_t> material;   // index into the material table
  std::vector<int32_t> body;        // bodies are bonded internally only
  std::vector<uint8_t> flags;       // ParticleFlag bits
  std::vector<uint8_t> anchor;      // anchor group of anchored particles (SimulationInput::motion)
  // Shards (bond_cuts.h): the cell each particle lies in (-1: none) and the strength, in 1/255,
  // of a bond from it to another cell. Both empty in scenes without shards.
  std::vector<int32_t> shard;
  std::vector<uint8_t> shard_strength;

  size_t size() const { return rest.size(); }
  void reserve(size_t n);
  // Appends one particle; returns its index.
  size_t add(Vec3 x, Vec3 v, real vol, real m, real tau0, uint16_t mat, int32_t body_id,
             uint8_t flag_bits = 0, uint8_t anchor_group = 0);
};

// A length no bond of `ps` exceeds: the largest family radius of `mt` with more than the slack
// family_reach (cuda/kernels/family.h) adds for the particles farthest from the origin.
double longest_bond_bound(const ParticleSet& ps, const MaterialTable& mt);

// Everything an engine needs to run: particles, material constants and step parameters.
// `springforces` in its screened form (cuda/kernels/bond_screen.h) while no bond broke in the
// last passes (kAuto), never (kOff), or in every pass (kAlways); the results are the same.
enum class BondScreen { kAuto, kOff, kAlways };

// The step as CUDA graphs where the scene allows (step_graphs.h): in small scenes (kAuto), in
// any (kOn) or never (kOff); the results are the same. The CPU backend has no graphs.
enum class StepGraphs { kAuto, kOn, kOff };

// Contact lists rebuilt for just the particles that left their skins where they are few
// (kIncremental, contact_relist.h), or every list at every build (kFull); the forces are the same.
enum class ContactRebuild { kIncremental, kFull };

struct SimulationInput {
  ParticleSet particles;
  MaterialTable materials;
  StepParams step;
  MotionScript motion;                // anchors, keyframed projectiles and colliders' motion, every step
  std::vector<Collider> colliders;    // rigid colliders (shape and contact law; motion.colliders moves them)
  std::vector<float> collider_grids;  // the mesh colliders' distance grids (Collider::grid_offset)
  std::vector<std::vector<Vec3>> collider_probes;  // per collider: a mesh's probe points (body_contact.h)
  std::vector<CutTriangle> cuts;                   // pre-cracks and weakened surfaces (bond_cuts.h)
  // Bonds weakened to their ends' shard strength, as bond_key pairs in ascending order (a
  // [[shards]] pattern: the cracks of an earlier run, bond_cuts.h); empty in most scenes.
  std::vector<uint64_t> face_bonds;
  // The solids of scattered bodies, where the ghost surface correction asks which stencil points
  // lie outside (body_solids.h); null or without a body: the ghost set-up's own rule.
  std::shared_ptr<const BodySolids> body_solids;
  bool contact = false;          // launch `collection` and `collisions`
  bool lattice_families = true;  // box-grid bodies find partners by offset (lattice_families.h)
  BondScreen screen = BondScreen::kAuto;
  ContactRebuild contact_rebuild = ContactRebuild::kIncremental;
  // Threads per particle in the GPU's bond loops (cuda/team.h): 1, 4, 8, 16 or 32; 0 chooses
  // from the scene (bond_threads.h). The CPU backend runs one.
  int bond_threads = 0;
  StepGraphs step_graphs = StepGraphs::kAuto;
};

}  // namespace pd
