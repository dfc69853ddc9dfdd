#include "host/app/shards_pattern.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda/engine/bond_cuts.h"
#include "cuda/engine/engine.h"
#include "host/app/checkpoint.h"
#include "host/fragments/components.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene_shards.h"

namespace pd {

namespace {

// The bonds of the checkpointed run in `c`, restored on the CPU over the particles of `input`
// (on each rank of a run over MPI by itself: every rank sets up the same input).
BondLists first_run_bonds(const SimulationInput& input, const RunCheckpoint& c) {
  SimulationInput first = input;
  if (c.explicit_families) first.lattice_families = false;
  const std::unique_ptr<Engine> engine = make_local_cpu_engine(first);
  engine->restore(c.engine);  // std::invalid_argument for other sizes
  BondLists bonds;
  engine->read_bonds(bonds);
  return bonds;
}

}  // namespace

void apply_shards_pattern(const Scene& scene, SetupResult& setup, double scale) {
  ShardsPatternReport& report = setup.pattern;
  report = {};
  SimulationInput& in = setup.input;
  ParticleSet& ps = in.particles;
  // Checked against the particles as the scene makes them, before any pattern changes them.
  const uint64_t fingerprint = setup_fingerprint(in);
  std::vector<uint64_t> faces;
  for (size_t t = 0; t < scene.shards.size(); ++t) {
    const SceneShards& g = scene.shards[t];
    if (g.pattern.empty()) continue;
    const std::string key = "shards[" + std::to_string(t) + "].pattern";
    const std::string where = "the run in '" + g.pattern + "'";
    RunCheckpoint c;
    try {
      c = read_checkpoint(g.pattern_path + "/" + kCheckpointFileName);
    } catch (const IoError& e) {
      throw SceneError(scene.path, key,
                       std::string(e.what()) +
                           " (allowed: the output folder of a run of this scene that wrote a checkpoint: "
                           "perifrac run --checkpoint-every N)");
    }
    if (c.scale != scale)
      throw SceneError(scene.path, key,
                       where + " was made at --scale " + format_number(c.scale) + ", this one at " +
                           format_number(scale) + " (allowed: the same scene at the same scale)");
    if (c.setup_hash != fingerprint)
      throw SceneError(scene.path, key,
                       where +
                           " was made from other particles or strain limits (another scene, seed, mesh "
                           "or --set; allowed: a run of this scene whose particles this one shares)");
    BondLists bonds;
    try {
      bonds = first_run_bonds(in, c);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.path, key, where + " does not fit this scene's families: " + e.what());
    }
    const BondsView v = bonds.view();

    // The first run's pieces, as its fragments.csv counts them (adjacent elements joined by
    // intact bonds, host/fragments/components.h).
    Components pieces;
    ComponentFinder(setup.adjacency, bonds).find(bonds, pieces);

    const uint8_t strength = shard_strength_byte(g.hold);
    const double hold = 255.0 / double(strength);
    // The dust's cells hold by their own factor where dust_hold is given.
    const uint8_t dust_strength = g.dust_hold ? shard_strength_byte(*g.dust_hold) : strength;
    const double dust_hold = 255.0 / double(dust_strength);
    if (ps.shard.empty()) {
      ps.shard.assign(ps.size(), -1);
      ps.shard_strength.assign(ps.size(), uint8_t(255));
    }
    std::vector<int64_t> dust_cell(ps.size(), -1);
    std::vector<bool> in_table(ps.size(), false);
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      if (!g.body.empty() && scene.bodies[b].name != g.body) continue;
      // The body's dust, for the dust's cells.
      std::vector<size_t> dust;
      int material = -1;
      for (size_t i = 0; i < ps.size(); ++i) {
        if (ps.body[i] != int32_t(b)) continue;
        material = ps.material[i];
        in_table[i] = true;
        if (pieces.size(size_t(pieces.index[i])) < kPatternPieceParticles) {
          dust.push_back(i);
        } else {
          ps.strain_limit0[i] = real(double(ps.strain_limit0[i]) * hold);
          ps.shard_strength[i] = strength;
        }
      }
      if (material < 0) continue;
      ++report.bodies;
      in.materials.m[material].compression_alpha *= real(hold);  // one table entry per body
      if (dust.empty()) continue;
      // The dust holds by dust_hold: a face between dust and the rest keeps the material's limit
      // (the smaller strength of its ends times the larger raised limit), and where dust_hold
      // differs from hold the dust takes a copy of the material entry for its own compression
      // strengthening.
      uint16_t dust_material = uint16_t(material);
      if (dust_strength != strength) {
        dust_material = copy_material_entry(scene, "shards[" + std::to_string(t) + "].dust_hold",
                                            "the dust of body '" + scene.bodies[b].name + "'", in.materials,
                                            uint16_t(material));
        in.materials.m[dust_material].compression_alpha *= real(dust_hold / hold);
        report.dust_materials.push_back({uint16_t(material), dust_material});
      }
      for (size_t i : dust) {
        ps.strain_limit0[i] = real(double(ps.strain_limit0[i]) * dust_hold);
        ps.shard_strength[i] = dust_strength;
        ps.material[i] = dust_material;
      }
      const std::vector<int64_t> cell = number_cells(scene, t, b, ps, dust, report.cells);
      for (size_t m = 0; m < dust.size(); ++m) dust_cell[dust[m]] = cell[m];
      report.dust += int64_t(dust.size());
    }
    // The faces: every bond the first run broke (in either direction) within these bodies, but
    // for those joining two particles of one dust cell.
    for (int32_t i = 0; i < v.n; ++i) {
      if (!in_table[size_t(i)]) continue;
      for (int32_t k = 0; k < v.count[i]; ++k) {
        const int32_t nb = v.neighbor[v.slot(i, k)];
        if (bond_intact(nb)) continue;
        const int32_t j = bond_partner(nb);
        if (dust_cell[size_t(i)] >= 0 && dust_cell[size_t(i)] == dust_cell[size_t(j)]) continue;
        faces.push_back(bond_key(i, j));
      }
    }
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  report.faces = int64_t(faces.size());
  in.face_bonds = std::move(faces);  // the patterns are all that list faces
}

SetupResult setup_scene_with_patterns(const Scene& scene, const SetupOptions& options) {
  SetupResult setup = setup_scene(scene, options);
  const auto start = std::chrono::steady_clock::now();
  apply_shards_pattern(scene, setup, options.scale);
  if (setup.pattern.bodies > 0)
    setup.stages.push_back(
        {"shards pattern", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  for (const auto& [body_material, dust_material] : setup.pattern.dust_materials)
    copy_material_summary(setup.materials, body_material, dust_material, " (shards dust)");
  return setup;
}

SetupResult setup_scene_with_patterns(const Scene& scene, double scale, Backend backend) {
  return setup_scene_with_patterns(scene, setup_options_for(scene, scale, backend));
}

}  // namespace pd
