// Scene files as text, shared by the tests that write them to a temporary folder and run them
// through the binary or a command.
#pragma once

namespace pd::testing {

// A plastic state-based plate hit by a block at 200 m/s: contact, plastic history and (at a lower
// strain limit) broken bonds. About 1,400 particles.
constexpr const char* kPlateImpactScene = R"([simulation]
steps_per_frame = 20
frames = 16
dt = "auto"
[contact]
enabled = true
stiffness = 1e9
[materials.metal]
model = "state_based"
density = 2700.0
youngs_modulus = 10e9
poisson_ratio = 0.3
strain_limit = 0.01
[materials.metal.plastic]
yield_stress = 20e6
[materials.block]
model = "state_based"
density = 7800.0
youngs_modulus = 50e9
poisson_ratio = 0.3
strain_limit = 0.5
[[bodies]]
material = "metal"
size = [0.04, 0.04, 0.006]
spacing = 0.002
[[bodies]]
material = "block"
center = [0.0, 0.0, 0.008]
size = [0.008, 0.008, 0.008]
spacing = 0.002
velocity = [0.0, 0.0, -200.0]
)";

}  // namespace pd::testing
