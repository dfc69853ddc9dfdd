// Domain decomposition of a partitioned run: which rank owns each particle (recursive coordinate
// bisection of the reference positions, weighted by the bonds a particle is expected to have),
// and each rank's local particles: its own, then the ghosts its bonds read (the other ranks'
// particles within a horizon of its own). A rank's own particles come interior first (no other
// rank holds them as ghosts, so none of their partners is a ghost), then boundary, each part in
// ascending global index; the ghosts in ascending global index. Every rank
// computes the whole partition from the same input, so the send and receive lists of the halo
// agree without a message.
#pragma once

#include <cstdint>
#include <vector>

#include "cuda/engine/particle_set.h"

namespace pd {

struct Partition {
  int ranks = 1;
  std::vector<int32_t> owner;                // per global particle
  std::vector<std::vector<int32_t>> owned;   // per rank: its particles, interior then boundary
  std::vector<int32_t> interior;             // per rank: how many of `owned` are interior
  std::vector<std::vector<int32_t>> ghosts;  // per rank: the bond ghosts it reads, ascending
};

// The owner of each particle and every rank's ghosts.
Partition partition_particles(const ParticleSet& particles, const MaterialTable& materials, int ranks);

// The same with each particle weighted by the bonds its family holds (plus one for the particle
// itself), as built: the split again where the estimate was off (a mesh's uneven elements).
Partition partition_particles(const ParticleSet& particles, const MaterialTable& materials, int ranks,
                              const std::vector<int32_t>& bonds);

// One rank's view of the partition.
struct RankLayout {
  int rank = 0;
  int32_t owned = 0;            // local particles [0, owned) are the rank's own
  int32_t interior = 0;         // of which [0, interior) read no ghost: their forces need no halo
  std::vector<int32_t> global;  // local index -> global index: own, then ghosts
  // Per peer rank, local indices in ascending global index: the own particles that are the peer's
  // ghosts (sent), and the ghosts the peer owns (received), so both sides list a message alike.
  std::vector<std::vector<int32_t>> send, recv;
};

RankLayout rank_layout(const Partition& partition, int rank);

// The particles of a layout, in its local order.
ParticleSet local_particles(const ParticleSet& all, const RankLayout& layout);

// The listed bonds (bond_key pairs of global indices, ascending: SimulationInput::face_bonds)
// whose two ends the layout holds, as keys of local indices, ascending.
std::vector<uint64_t> local_face_bonds(const std::vector<uint64_t>& faces, const RankLayout& layout,
                                       size_t global_particles);

// Particles, estimated bonds and ghosts per rank, and the imbalance (largest / mean estimated
// bonds), for the start-up report.
struct PartitionBalance {
  std::vector<int64_t> particles, ghosts;
  std::vector<double> weight;
  double imbalance = 1;
};
PartitionBalance partition_balance(const Partition& partition, const ParticleSet& particles,
                                   const MaterialTable& materials);

}  // namespace pd
