// Out-of-memory path on the GPU: a scene sized past the device's memory is refused before the
// run starts, and bond lists that do not fit are refused before they are allocated.
#include <gtest/gtest.h>

#include <cstdlib>

#include "cuda/engine/engine.h"
#include "cuda/engine/memory_budget.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"
#include "tests/support/fixtures.h"
#include "tests/support/require_gpu.h"

namespace pd {
namespace {

// 800 x 800 x 800 particles (5.1e8): past any current GPU at ~900 B per particle.
TEST(GpuMemory, SceneLargerThanTheDeviceIsRefusedBeforeSetup) {
  REQUIRE_GPU();
  const Scene scene = parse_scene(
      "[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n"
      "[[bodies]]\nmaterial = \"glass\"\nsize = [0.8, 0.8, 0.8]\nspacing = 0.001\n",
      "huge.toml");
  const ParticleBudget budget = particle_budget(Backend::kCuda, 3, false, true);
  ASSERT_LT(budget.max_particles, 512000000) << "a GPU with more than ~450 GB?";
  SetupOptions options;
  options.max_particles = budget.max_particles;
  options.budget_why = budget.why;
  try {
    setup_scene(scene, options);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("free on the GPU"), std::string::npos) << m;
    EXPECT_NE(m.find("bodies[0].spacing"), std::string::npos) << m;
  }
}

TEST(GpuMemory, BondListsThatDoNotFitAreRefusedBeforeAllocation) {
  REQUIRE_GPU();
  setenv("PERIFRAC_DEVICE_MEMORY_MB", "0.1", 1);
  try {
    make_cuda_engine(testing::lattice_block(12, 12, 12, 1e-3));
    ADD_FAILURE() << "accepted";
  } catch (const ResourceError& e) {
    EXPECT_NE(std::string(e.what()).find("GPU memory"), std::string::npos) << e.what();
  }
  unsetenv("PERIFRAC_DEVICE_MEMORY_MB");
  EXPECT_NO_THROW(make_cuda_engine(testing::lattice_block(12, 12, 12, 1e-3)));
}

}  // namespace
}  // namespace pd
