#include "cuda/engine/stable_step.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <random>
#include <vector>

namespace pd {

namespace {

// One probe of the engine's forces, at the saved state plus a displacement per particle.
class ForceProbe {
 public:
  ForceProbe(Engine& engine, const SimulationInput& in) : engine_(engine), n_(in.particles.size()) {
    engine_.save(saved_);
    probe_ = saved_;
    std::fill(probe_.vel.begin(), probe_.vel.end(), Vec3{0, 0, 0});
    std::fill(probe_.force.begin(), probe_.force.end(), Vec3{0, 0, 0});
    double spacing = INFINITY;
    for (int32_t k = 0; k < in.materials.count; ++k)
      if (in.materials.m[k].spacing > 0) spacing = std::min(spacing, double(in.materials.m[k].spacing));
    amplitude_ = kProbeStrain * (std::isfinite(spacing) ? spacing : 1.0);
    broken_ = engine_.broken_bonds();
    baseline_ = forces(std::vector<double>(3 * n_, 0.0), 0.0);
  }
  ~ForceProbe() { engine_.restore(saved_); }

  // K u (the stiffness's product, linearized at the saved state), from the forces at a
  // displacement s u, s scaling u's largest component to the probe's amplitude.
  std::vector<double> stiffness_times(const std::vector<double>& u) {
    double largest = 0;
    for (double x : u) largest = std::max(largest, std::abs(x));
    std::vector<double> ku(u.size(), 0.0);
    if (largest == 0) return ku;
    const double s = amplitude_ / largest;
    const std::vector<double> f = forces(u, s);
    for (size_t k = 0; k < ku.size(); ++k) ku[k] = -(f[k] - baseline_[k]) / s;
    return ku;
  }

 private:
  // One step from the saved state displaced by s u, with no velocity and no force: the
  // positions stay where they are (u += dt (v + dt/2 f/m) adds zero) and the forces are the
  // new positions'.
  std::vector<double> forces(const std::vector<double>& u, double s) {
    for (size_t i = 0; i < n_; ++i) {
      const Vec4 d = saved_.disp[i];
      probe_.disp[i] = {real(double(d.x) + s * u[3 * i]), real(double(d.y) + s * u[3 * i + 1]),
                        real(double(d.z) + s * u[3 * i + 2]), d.w};
    }
    engine_.restore_particles(probe_);
    engine_.advance(1);
    engine_.read_state(state_);
    // A bond that broke (one at its limit in the state probed) is put back for the next probe.
    if (engine_.broken_bonds() != broken_) engine_.restore(saved_);
    std::vector<double> f(3 * n_);
    for (size_t i = 0; i < n_; ++i) {
      f[3 * i] = state_.force[i].x;
      f[3 * i + 1] = state_.force[i].y;
      f[3 * i + 2] = state_.force[i].z;
    }
    return f;
  }

  Engine& engine_;
  size_t n_;
  EngineSnapshot saved_, probe_;
  ParticleState state_;
  double amplitude_ = 0;
  int64_t broken_ = 0;  // broken bonds in the state saved
  std::vector<double> baseline_;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
  return s;
}

}  // namespace

StableStep measure_stable_step(Engine& engine, const SimulationInput& in, const StableStepOptions& options) {
  const ParticleSet& ps = in.particles;
  const size_t n = ps.size();
  // 1 / sqrt(m) per free degree of freedom; 0 where the particle is held or has no mass.
  std::vector<double> scale(3 * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    if (!(ps.flags[i] & kAnchored) && ps.mass[i] > 0)
      scale[3 * i] = scale[3 * i + 1] = scale[3 * i + 2] = 1.0 / std::sqrt(double(ps.mass[i]));

  // The start vector: uniform in [-1, 1] on the free degrees of freedom.
  std::mt19937_64 rng(options.seed);
  std::vector<double> q(3 * n, 0.0), q_prev(3 * n, 0.0);
  for (size_t k = 0; k < q.size(); ++k) {
    const double x = double(rng() >> 11) * 0x1p-53;
    q[k] = scale[k] > 0 ? 2 * x - 1 : 0;
  }
  StableStep out;
  const double norm0 = std::sqrt(dot(q, q));
  if (norm0 == 0) return out;
  for (double& x : q) x /= norm0;

  ForceProbe probe(engine, in);
  std::vector<double> alpha, beta;
  std::vector<double> u(3 * n);
  double beta_prev = 0;
  for (int k = 0; k < options.max_iterations; ++k) {
    // z = M^-1/2 K M^-1/2 q
    for (size_t d = 0; d < u.size(); ++d) u[d] = scale[d] * q[d];
    std::vector<double> z = probe.stiffness_times(u);
    for (size_t d = 0; d < z.size(); ++d) z[d] *= scale[d];
    const double a = dot(q, z);
    for (size_t d = 0; d < z.size(); ++d) z[d] -= a * q[d] + beta_prev * q_prev[d];
    const double b = std::sqrt(dot(z, z));
    alpha.push_back(a);
    out.iterations = k + 1;

    // The tridiagonal's largest eigenvalue and its pair's residual b |s_last|.
    const int m = int(alpha.size());
    Eigen::VectorXd diag = Eigen::Map<Eigen::VectorXd>(alpha.data(), m);
    Eigen::VectorXd sub =
        m > 1 ? Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(beta.data(), m - 1)) : Eigen::VectorXd(0);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver;
    solver.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);
    const double theta = solver.eigenvalues()(m - 1);
    out.residual = b * std::abs(solver.eigenvectors()(m - 1, m - 1));
    out.lambda_max = theta + out.residual;
    if (b <= 1e-12 * std::abs(theta) || (k >= 4 && out.residual <= options.tolerance * theta)) break;

    beta.push_back(b);
    beta_prev = b;
    q_prev.swap(q);
    for (size_t d = 0; d < z.size(); ++d) q[d] = z[d] / b;
  }
  out.seconds = out.lambda_max > 0 ? 2.0 / std::sqrt(out.lambda_max) : INFINITY;
  return out;
}

double rounded_down_step(double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds)) return seconds;
  int e = 0;
  const double mantissa = std::frexp(seconds, &e);  // [0.5, 1)
  return std::ldexp(std::floor(mantissa * 256.0) / 256.0, e);
}

}  // namespace pd
