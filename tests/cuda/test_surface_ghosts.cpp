// The ghost surface correction (cuda/kernels/surface_ghosts.h, cuda/engine/surface_ghosts.h) on
// the CPU-reference engine: surface particles store the interior's energy under uniform strains,
// the forces are the energy's gradient and keep momentum and angular momentum, the stable step
// takes the ghosts, and the ghosts go with the first broken bond, their energy booked.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "cuda/engine/cut_triangle.h"
#include "cuda/engine/engine.h"
#include "cuda/engine/material.h"
#include "cuda/engine/memory_budget.h"
#include "cuda/engine/surface_ghosts.h"
#include "cuda/kernels/surface_ghosts.h"
#include "tests/support/fixtures.h"
#include "tests/support/scoped_env.h"

namespace pd {
namespace {

constexpr double kLambda = 1e-3;

// A block with the ghost correction in place of the factors, PMB or LPS.
SimulationInput ghost_block(bool state_based, int nx, int ny, int nz) {
  SimulationInput in = state_based ? testing::state_block(nx, ny, nz, kLambda, 0.5, false)
                                   : testing::lattice_block(nx, ny, nz, kLambda, 0.5);
  Material& m = in.materials.m[0];
  m.partial_volumes = 1;
  m.surface_correction = 0;
  m.ghost_correction = 1;
  return in;
}

// The engine after one step that moves every particle by u(x): velocities u / dt, a step so
// short that the forces move nothing further.
std::unique_ptr<Engine> displaced(SimulationInput in, const std::function<Vec3(Vec3)>& u) {
  in.step.dt = real(1e-9);
  for (size_t i = 0; i < in.particles.size(); ++i)
    in.particles.velocity[i] = u(in.particles.rest[i]) * real(1e9);
  auto e = make_cpu_engine(in);
  e->advance(1);
  return e;
}

// The displacement field u = eps x.
std::function<Vec3(Vec3)> uniform_strain(const double (&eps)[3][3]) {
  return [&eps](Vec3 x) {
    const double p[3] = {x.x, x.y, x.z};
    double u[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) u[a] += eps[a][b] * p[b];
    return Vec3{real(u[0]), real(u[1]), real(u[2])};
  };
}

// The interior lattice family's energy density under a uniform strain eps (small: stretches
// taken linear), as the engine's sums define it.
double interior_energy_density(const Material& m, const double eps[3][3]) {
  const double lambda = double(m.spacing), radius = double(m.family_radius()) * (1 + 1e-6);
  const int reach = int(radius / lambda) + 1;
  double pmb = 0, mw = 0, theta_sum = 0;
  std::vector<std::pair<double, double>> bonds;  // (r, e) with weight
  std::vector<double> weights;
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        const double r = lambda * std::sqrt(double(x * x + y * y + z * z));
        if (r == 0 || r > radius) continue;
        const double n[3] = {x * lambda / r, y * lambda / r, z * lambda / r};
        double s = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) s += n[a] * eps[a][b] * n[b];
        const double w = double(volume_fraction(real(r), m)) * lambda * lambda * lambda;
        pmb += 0.25 * double(m.micromodulus) * s * s * r * w;
        const double omega = double(m.horizon) / r;
        mw += omega * r * r * w;
        theta_sum += omega * r * (s * r) * w;
        bonds.push_back({r, s * r});
        weights.push_back(omega * w);
      }
  if (m.model != kStateBased) return pmb;
  const double theta = 3 * theta_sum / mw;
  double dev = 0;
  for (size_t k = 0; k < bonds.size(); ++k) {
    const double ed = bonds[k].second - theta * bonds[k].first / 3;
    dev += 7.5 * double(m.shear_modulus) / mw * weights[k] * ed * ed;
  }
  return 0.5 * double(m.bulk_modulus) * theta * theta + dev;
}

// Under uniform strains every particle, at faces, edges and corners too, stores the interior's
// energy: the block's strain energy is its volume times the interior density (to float
// round-off), where the uncorrected models are off by percents (PMB 40-45% soft; LPS soft or
// stiff by the strain).
TEST(SurfaceGhosts, UniformStrainsStoreTheInteriorsEnergy) {
  const double strains[3][3][3] = {{{1e-5, 0, 0}, {0, 0, 0}, {0, 0, 0}},
                                   {{0, 5e-6, 0}, {5e-6, 0, 0}, {0, 0, 0}},
                                   {{1e-5, 5e-6, 2e-6}, {5e-6, -3e-6, 1e-6}, {2e-6, 1e-6, 4e-6}}};
  for (bool state : {false, true})
    for (const auto& eps : strains) {
      const SimulationInput in = ghost_block(state, 8, 7, 6);
      const auto strain = uniform_strain(eps);
      auto e = displaced(in, strain);
      const double exact = double(in.particles.size()) * kLambda * kLambda * kLambda *
                           interior_energy_density(in.materials.m[0], eps);
      const double ratio = e->energy().strain / exact;
      SimulationInput plain = in;
      plain.materials.m[0].ghost_correction = 0;
      const double uncorrected = displaced(plain, strain)->energy().strain / exact;
      std::printf("  %s: energy / interior's %.6f with ghosts, %.4f without\n", state ? "LPS" : "PMB", ratio,
                  uncorrected);
      EXPECT_NEAR(ratio, 1.0, 2e-4);
      EXPECT_GT(std::fabs(uncorrected - 1), 0.01);
      EXPECT_GT(e->surface_ghosts().ghosted, 0);
    }
}

// A smooth random displacement: the forces sum to zero, exert no torque, and are minus the
// gradient of the strain energy (central differences at a corner, an edge and a face particle).
TEST(SurfaceGhosts, ForcesKeepMomentumAndAreTheEnergysGradient) {
  for (bool state : {false, true}) {
    const SimulationInput in = ghost_block(state, 6, 5, 5);
    auto field = [](Vec3 x) {
      const double a = x.x / kLambda, b = x.y / kLambda, c = x.z / kLambda;
      return Vec3{real(2e-8 * (std::sin(0.9 * a + 0.3 * c) + 0.2 * b * b)),
                  real(2e-8 * std::cos(0.7 * b - 0.4 * a) * (1 + 0.1 * c)),
                  real(2e-8 * std::sin(0.5 * a * b / 6))};
    };
    auto e = displaced(in, field);
    ParticleState s;
    e->read_state(s);
    double sum[3] = {0, 0, 0}, torque[3] = {0, 0, 0}, scale = 0, arm = 0;
    for (size_t i = 0; i < in.particles.size(); ++i) {
      const Vec3 x = in.particles.rest[i] + s.disp[i], f = s.force[i];
      const Vec3 t = cross(x, f);
      sum[0] += f.x, sum[1] += f.y, sum[2] += f.z;
      torque[0] += t.x, torque[1] += t.y, torque[2] += t.z;
      scale += length(f);
      arm += length(f) * length(x);
    }
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::fabs(sum[a]), 1e-5 * scale) << "axis " << a;
      EXPECT_LT(std::fabs(torque[a]), 1e-5 * arm) << "axis " << a;
    }
    // particles: a corner (0), one on an edge (2), one on a face (2 + 6 * 2), one inside
    for (int probe : {0, 2, 2 + 6 * 2, 2 + 6 * 2 + 30 * 2}) {
      for (int axis = 0; axis < 3; ++axis) {
        const double h = 2e-9;
        auto moved = [&](double sign) {
          return [&, sign](Vec3 x) {
            Vec3 u = field(x);
            if (x.x == in.particles.rest[size_t(probe)].x && x.y == in.particles.rest[size_t(probe)].y &&
                x.z == in.particles.rest[size_t(probe)].z)
              (axis == 0 ? u.x : axis == 1 ? u.y : u.z) += real(sign * h);
            return u;
          };
        };
        const double gradient =
            (displaced(in, moved(1))->energy().strain - displaced(in, moved(-1))->energy().strain) / (2 * h);
        const Vec3 f = s.force[size_t(probe)];
        const double force = axis == 0 ? f.x : axis == 1 ? f.y : f.z;
        EXPECT_NEAR(-gradient, force, 2e-3 * length(f) + 1e-6 * scale / double(in.particles.size()))
            << (state ? "LPS" : "PMB") << " particle " << probe << " axis " << axis;
      }
    }
  }
}

// The stable step counts the ghost bonds (their forces reach the whole family, with the fit's
// extrapolation): shorter than without them, and a free block vibrating at half of it keeps its
// energy.
TEST(SurfaceGhosts, TheStableStepTakesTheGhosts) {
  for (bool state : {false, true}) {
    SimulationInput in = ghost_block(state, 10, 5, 5);
    SimulationInput plain = in;
    plain.materials.m[0].ghost_correction = 0;
    const double with = make_cpu_engine(in)->critical_time_step(),
                 without = make_cpu_engine(plain)->critical_time_step();
    std::printf("  %s: stable step with ghosts %.3g s, without %.3g s (%.2fx)\n", state ? "LPS" : "PMB", with,
                without, without / with);
    EXPECT_LT(with, without);
    in.step.dt = real(0.5 * with);
    for (size_t i = 0; i < in.particles.size(); ++i)
      in.particles.velocity[i] = {0, real(0.01 * std::cos(M_PI * in.particles.rest[i].x / 9e-3)), 0};
    auto e = make_cpu_engine(in);
    const Energy e0 = e->energy();
    double worst = 0;
    for (int k = 0; k < 20; ++k) {
      e->advance(50);
      worst = std::max(worst, std::fabs(e->energy().balance() - e0.balance()) / e0.kinetic);
    }
    EXPECT_LT(worst, 1e-3);
  }
}

// Pulled apart: the particles along the crack lose their ghosts at their first broken bond, and
// the books still balance (the ghosts' energy released with the bonds'). PMB's books are exact
// to the step's first-order error; LPS books a breaking bond's deviatoric share only (its effect
// on theta is not booked), so there the ghosted run's error is held to the uncorrected run's.
TEST(SurfaceGhosts, GhostsGoWithTheFirstBrokenBond) {
  for (bool state : {false, true}) {
    double error[2] = {0, 0}, released[2] = {0, 0}, kinetic = 0;
    for (int ghosts : {1, 0}) {
      SimulationInput in = ghost_block(state, 16, 4, 4);
      in.materials.m[0].ghost_correction = uint8_t(ghosts);
      in.particles.strain_limit0.assign(in.particles.size(), real(2e-4));
      if (state) in.materials.m[0].chen_fracture = 0;
      in = testing::pulled_apart(in, 16, kLambda, 1.0);
      in.step.dt = real(0.25 * make_cpu_engine(ghost_block(state, 16, 4, 4))->critical_time_step());
      auto e = make_cpu_engine(in);
      const Energy e0 = e->energy();
      e->advance(int64_t(2e-6 / in.step.dt));
      const Energy e1 = e->energy();
      ASSERT_GT(e->broken_bonds(), 0);
      error[ghosts] = std::fabs(e1.balance() - e0.balance());
      released[ghosts] = e1.released;
      kinetic = e0.kinetic;
    }
    std::printf("  %s: released %.3g J, balance error %.3g J (without ghosts %.3g J, %.3g J)\n",
                state ? "LPS" : "PMB", released[1], error[1], released[0], error[0]);
    EXPECT_GT(released[1], released[0]);  // the ghosts' energy too
    if (state)
      EXPECT_LT(error[1], 1.5 * error[0] + 1e-3 * kinetic);
    else
      EXPECT_LT(error[1], 0.25 * released[1]);
  }
}

// Scattered particles (a jittered grid standing in for tets and Voronoi cells): the ghosts fill
// what a surface particle's family lacks of the interior's volume, so the block stores nearly the
// interior's energy under a uniform strain, where the uncorrected PMB block stores 30-40% less.
TEST(SurfaceGhosts, ScatteredParticlesGetTheMissingVolume) {
  SimulationInput in = testing::lattice_block(10, 9, 8, kLambda, 0.5, 0.4);
  Material& m = in.materials.m[0];
  m.surface_correction = 0;
  m.ghost_correction = 1;
  const double eps[3][3] = {{1e-5, 2e-6, 0}, {2e-6, -3e-6, 0}, {0, 0, 4e-6}};
  const auto strain = uniform_strain(eps);
  double volume = 0;
  for (real v : in.particles.volume) volume += double(v);
  const double exact = volume * interior_energy_density(m, eps);
  auto e = displaced(in, strain);
  SimulationInput plain = in;
  plain.materials.m[0].ghost_correction = 0;
  const double with = e->energy().strain / exact, without = displaced(plain, strain)->energy().strain / exact;
  const SurfaceGhostCounts counts = e->surface_ghosts();
  std::printf(
      "  jittered block: energy / interior's %.4f with ghosts (%lld ghosted, %lld on the linear fit), "
      "%.4f without\n",
      with, (long long)counts.ghosted, (long long)counts.linear, without);
  EXPECT_NEAR(with, 1.0, 0.05);
  EXPECT_LT(without, 0.8);
}

// A box solid for the ghost set-up's test of where a scattered body ends (body_solids.h).
class BoxSolid final : public BodySolids {
 public:
  BoxSolid(Vec3 lo, Vec3 hi) : lo_(lo), hi_(hi) {}
  bool has(int32_t body) const override { return body == 0; }
  void inside_along_x(int32_t, double x0, double dx, double y, double z, int count,
                      uint8_t* inside) const override {
    for (int k = 0; k < count; ++k) inside[k] = uint8_t(contains(x0 + k * dx, y, z));
  }
  bool contains(double x, double y, double z) const {
    return x > lo_.x && x < hi_.x && y > lo_.y && y < hi_.y && z > lo_.z && z < hi_.z;
  }

 private:
  Vec3 lo_, hi_;
};

// Scattered particles whose body's solid is known: every ghost lies outside it, where without the
// solid the set-up puts some inside it (stencil points far from every particle between the
// scattered partners), and the block still stores the interior's energy under a uniform strain.
TEST(SurfaceGhosts, ScatteredParticlesTakeGhostsOutsideTheirSolid) {
  SimulationInput in = testing::lattice_block(10, 9, 8, kLambda, 0.5, 0.4);
  Material& m = in.materials.m[0];
  m.surface_correction = 0;
  m.ghost_correction = 1;
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const Vec3& x : in.particles.rest) {
    lo = {std::fmin(lo.x, x.x), std::fmin(lo.y, x.y), std::fmin(lo.z, x.z)};
    hi = {std::fmax(hi.x, x.x), std::fmax(hi.y, x.y), std::fmax(hi.z, x.z)};
  }
  const real half = real(0.5 * kLambda);  // the cubes' faces past the outermost centres
  const auto solid = std::make_shared<BoxSolid>(lo - Vec3{half, half, half}, hi + Vec3{half, half, half});
  BondLists families;
  make_cpu_engine(in)->read_bonds(families);
  const std::vector<int32_t> cut_count = families.count;
  // The ghosts' points inside the solid, with and without it.
  auto inside_points = [&](const GhostTables& t) {
    int64_t inside = 0;
    for (int32_t g = 0; g < t.size(); ++g) {
      const Vec3 x = in.particles.rest[size_t(t.particle[size_t(g)])];
      for (int32_t o = t.first[size_t(g)]; o < t.first[size_t(g) + 1]; ++o) {
        const Vec3 p = x + xyz(t.offset[size_t(o)]);
        inside += solid->contains(p.x, p.y, p.z);
      }
    }
    return inside;
  };
  const GhostTables with = surface_ghosts(in.particles, in.materials, families, cut_count, solid.get());
  const GhostTables without = surface_ghosts(in.particles, in.materials, families, cut_count);
  std::printf(
      "  jittered block: %d ghosted, %zu ghosts, %lld inside the box; without the solid %d, %zu, %lld\n",
      with.size(), with.offset.size(), (long long)inside_points(with), without.size(), without.offset.size(),
      (long long)inside_points(without));
  EXPECT_GT(with.size(), 0);
  EXPECT_EQ(inside_points(with), 0);
  EXPECT_GT(inside_points(without), 0);

  in.body_solids = solid;
  const double eps[3][3] = {{1e-5, 2e-6, 0}, {2e-6, -3e-6, 0}, {0, 0, 4e-6}};
  double volume = 0;
  for (real v : in.particles.volume) volume += double(v);
  const double ratio =
      displaced(in, uniform_strain(eps))->energy().strain / (volume * interior_energy_density(m, eps));
  std::printf("  jittered block with its solid: energy / interior's %.4f\n", ratio);
  EXPECT_NEAR(ratio, 1.0, 0.05);
}

// Particles that miss bonds but cannot have ghosts: a plate one particle thick (its families
// do not span the quadratic fit) and the particles of a pre-cut block.
TEST(SurfaceGhosts, ThinFamiliesAndPreCracksGetNone) {
  const auto thin = make_cpu_engine(ghost_block(false, 8, 8, 1))->surface_ghosts();
  EXPECT_EQ(thin.ghosted, 0);
  EXPECT_EQ(thin.thin, 64);
  SimulationInput cut = ghost_block(false, 10, 6, 6);
  CutTriangle t;  // the plane x = 4.5 mm over the lower half of the block's height
  t.corner = {{{4.5e-3, -1e-3, -1e-3}, {4.5e-3, 3e-3, -1e-3}, {4.5e-3, -1e-3, 7e-3}}};
  cut.cuts.push_back(t);
  const auto counts = make_cpu_engine(cut)->surface_ghosts();
  EXPECT_GT(counts.precracked, 0);
  EXPECT_GT(counts.ghosted, 0);
}

// The ghost tables count against the backend's memory: a body whose bonds fit but whose tables
// do not is refused with a message that names them and the remedy, before they are allocated.
TEST(SurfaceGhosts, TablesThatDoNotFitAreRefused) {
  const SimulationInput in = ghost_block(false, 12, 12, 4);  // every particle within delta of a face
  const auto fits = make_cpu_engine(in);
  const SurfaceGhostCounts counts = fits->surface_ghosts();
  EXPECT_EQ(counts.ghosted, 12 * 12 * 4);
  // ~4 KB of tables per ghosted particle here (the push table and the mirror rows ~2.5 KB of
  // them) against ~0.3 KB of bond slots: a cap between.
  const testing::ScopedEnv cap("PERIFRAC_HOST_MEMORY_MB", "0.4");
  try {
    make_cpu_engine(in);
    FAIL() << "accepted";
  } catch (const ResourceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ghost surface correction"), std::string::npos) << m;
    EXPECT_NE(m.find("576 ghosted particles"), std::string::npos) << m;
    EXPECT_NE(m.find("host memory"), std::string::npos) << m;
    EXPECT_NE(m.find("surface_correction to true"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace pd
