// Memory budget: an oversized scene is refused before its particles are made, and an engine
// whose bond lists do not fit is refused before they are allocated.
#include "cuda/engine/memory_budget.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <future>

#include "host/geometry/tetgen.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/support/fixtures.h"
#include "tests/support/scoped_env.h"

namespace pd {
namespace {

using testing::ScopedEnv;

TEST(MemoryBudget, BondsPerParticleCountsTheCellsOfThePartialVolumeSphere) {
  // delta = 3 lambda with partial volumes reaches 3.5 lambda: 4/3 pi 3.5^3 = 179.6 cells.
  EXPECT_NEAR(bonds_per_particle(3), 179.59, 0.01);
  EXPECT_GT(engine_bytes_per_particle(3, true, false), engine_bytes_per_particle(3, false, false));
  // The surface correction's factor: 2 B per bond slot, padding included.
  EXPECT_NEAR(engine_bytes_per_particle(3, false, true) - engine_bytes_per_particle(3, false, false),
              2 * 179.59 * 1.15, 1);
}

TEST(MemoryBudget, HostMemoryIsReadAndCanBeCapped) {
  EXPECT_GT(host_available_bytes(), size_t(64) << 20);  // any machine that runs the tests
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "10");
  EXPECT_EQ(host_available_bytes(), size_t(10) << 20);
  EXPECT_EQ(backend_available_bytes(Backend::kCpu), size_t(10) << 20);
}

TEST(MemoryBudget, BadCapIsAnErrorNamingTheVariable) {
  for (const char* bad : {"lots", "-1", "12MB", "nan"}) {
    const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", bad);
    try {
      host_available_bytes();
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("PERIFRAC_HOST_MEMORY_MB"), std::string::npos) << e.what();
    }
  }
}

TEST(MemoryBudget, BudgetFollowsTheFreeMemory) {
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "100");
  const ParticleBudget b = particle_budget(Backend::kCpu, 3, false, true);
  const double per = kHostBytesPerParticle + engine_bytes_per_particle(3, false, true);
  EXPECT_EQ(b.max_particles, int64_t(100.0 * (1 << 20) / per));
  EXPECT_NE(b.why.find("free host memory"), std::string::npos) << b.why;
}

// Split over 4 ranks, 2 on this host: each rank's engine holds a quarter (and its ghosts), while
// both ranks of the host hold the whole particle set.
TEST(MemoryBudget, RanksShareTheEngineButEachHoldsTheParticleSet) {
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "100");
  const ParticleBudget b = particle_budget(Backend::kCpu, 3, false, true, 4, 2);
  const double per =
      2 * (kHostBytesPerParticle + engine_bytes_per_particle(3, false, true) * kRankGhostAllowance / 4);
  EXPECT_EQ(b.max_particles, int64_t(100.0 * (1 << 20) / per));
  EXPECT_NE(b.why.find("split over 4 ranks"), std::string::npos) << b.why;
}

// A million-particle box against a 20 MiB budget: refused at once, naming the key and the limit.
TEST(MemoryBudget, OversizedSceneIsRefusedBeforeItsParticlesAreMade) {
  const Scene scene = parse_scene(
      "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
      "[[bodies]]\nmaterial = \"glass\"\nsize = [0.1, 0.1, 0.1]\nspacing = 0.001\n",
      "big.toml");
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "20");
  const ParticleBudget budget = particle_budget(Backend::kCpu, 3, false, true);
  SetupOptions options;
  options.max_particles = budget.max_particles;
  options.budget_why = budget.why;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    setup_scene(scene, options);
    FAIL() << "a 1M-particle scene was accepted with a " << budget.max_particles << "-particle budget";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("big.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("bodies[0].spacing"), std::string::npos) << m;
    EXPECT_NE(m.find("1000000 particles"), std::string::npos) << m;
    EXPECT_NE(m.find("free host memory"), std::string::npos) << m;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.5);
}

// The budget found on a thread of its own (setup_options_later, as `perifrac run` sets up): the
// same refusal; a tet body's comes once its TetGen has started, which it stops.
TEST(MemoryBudget, ABudgetFoundBesideTheSetUpRefusesTheSame) {
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "20");
  const Scene box = parse_scene(
      "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
      "[[bodies]]\nmaterial = \"glass\"\nsize = [0.1, 0.1, 0.1]\nspacing = 0.001\n",
      "big.toml");
  std::promise<Backend> cpu;
  cpu.set_value(Backend::kCpu);
  const std::shared_future<Backend> backend = cpu.get_future().share();
  try {
    setup_scene(box, setup_options_later(box, 1, backend));
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bodies[0].spacing"), std::string::npos) << m;
    EXPECT_NE(m.find("1000000 particles"), std::string::npos) << m;
    EXPECT_NE(m.find("free host memory"), std::string::npos) << m;
  }
  if (find_tetgen().empty()) GTEST_SKIP() << "tetgen is not installed (the tet body's refusal not checked)";
  const Scene tets = parse_scene(
      "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
      "[[bodies]]\nmaterial = \"glass\"\nshape = \"sphere\"\nradius = 0.1\nspacing = 0.0005\n"
      "particles = \"tets\"\n",
      "fine.toml");
  const ScopedEnv no_cache("PERIFRAC_TET_CACHE", "off");
  const auto t0 = std::chrono::steady_clock::now();
  try {
    setup_scene(tets, setup_options_later(tets, 1, backend));
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bodies[0].particles"), std::string::npos) << m;
    EXPECT_NE(m.find("would need about"), std::string::npos) << m;
  }
  // (TetGen at this volume bound, 16 million tets, would run for minutes.)
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5);
}

// The engine's exact check: families counted, then refused before the bond arrays exist.
TEST(MemoryBudget, EngineRefusesBondListsThatDoNotFit) {
  const SimulationInput in = testing::lattice_block(12, 12, 12, 1e-3);
  const ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "0.1");
  try {
    make_cpu_engine(in);
    FAIL() << "accepted";
  } catch (const ResourceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bond slots"), std::string::npos) << m;
    EXPECT_NE(m.find("host memory"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace pd
