#include "app/study/stability_theory.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/integrators/integrator.h"

namespace wobble {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Spectral radius of one step of h on x'' = -x - 2 zeta x' (omega = 1), through the integrator itself.
double spectralRadius(std::string_view integrator, const MassSpringSystem& oscillator, double h) {
  Eigen::Matrix2d map;
  for (int column = 0; column < 2; ++column) {
    auto method = makeIntegrator(integrator);
    VecX x = oscillator.initialPositions(), v = VecX::Zero(6);
    const double unit = 1e-3;  // small beside the rest length 1; the motion is along the spring, so exactly linear
    (column == 0 ? x[3] : v[3]) += unit;
    method->step(oscillator, 0, h, x, v);
    map(0, column) = (x[3] - 1) / unit;
    map(1, column) = v[3] / unit;
  }
  return map.eigenvalues().cwiseAbs().maxCoeff();
}

MassSpringSystem makeOscillator(double zeta) {
  Body body;
  body.name = "oscillator";
  body.kind = "theory";
  body.x = VecX::Zero(6);
  body.x[3] = 1;
  body.v = VecX::Zero(6);
  body.mass = VecX::Ones(2);
  body.pinned = {true, false};
  body.springs.add(0, 1, 1.0, 1.0, 2 * zeta, SpringType::Structural);
  MassSpringSystem system(Vec3::Zero());
  system.addBody(std::move(body));
  return system;
}

}  // namespace

double stableOmegaH(std::string_view integrator, double zeta) {
  if (const IntegratorTraits& traits = integratorTraits(integrator); traits.adaptive || traits.a_stable) return kInf;
  const MassSpringSystem oscillator = makeOscillator(zeta);
  const auto stable = [&](double y) { return spectralRadius(integrator, oscillator, y) <= 1 + 1e-12; };
  // Scan up in steps of 0.02 to the first unstable value, then bisect; 0 when unstable at once.
  double lo = 0, hi = 0.02;
  while (stable(hi)) {
    lo = hi;
    hi += 0.02;
    if (hi > 50) return kInf;
  }
  if (lo == 0 && !stable(1e-6)) return 0;
  for (int i = 0; i < 40 && hi - lo > 1e-6 * hi; ++i) {
    const double mid = (lo + hi) / 2;
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

double stableStep(std::string_view integrator, double omega_max, double r) {
  if (!(omega_max > 0)) return kInf;
  double best = kInf;
  for (int i = 0; i <= 40; ++i) {
    const double w = omega_max * std::pow(100.0, -i / 40.0);
    best = std::min(best, stableOmegaH(integrator, r * w / 2) / w);
  }
  return best;
}

double gershgorinOmegaMax(const MassSpringSystem& system) {
  VecX sum = VecX::Zero(system.particleCount());
  const Springs& s = system.springs();
  for (std::size_t i = 0; i < s.size(); ++i) {
    sum[s.a[i]] += s.ks[i];
    sum[s.b[i]] += s.ks[i];
  }
  double worst = 0;
  for (int i = 0; i < system.particleCount(); ++i)
    if (system.inverseMass()[i] != 0) worst = std::max(worst, 2 * sum[i] * system.inverseMass()[i]);
  return std::sqrt(worst);
}

double powerIterationOmegaMax(const MassSpringSystem& system, int iterations) {
  const VecX& x = system.initialPositions();
  const Eigen::Index n = x.size();
  Triplets dfdx, dfdv;
  system.addForceJacobians(0, x, VecX::Zero(n), dfdx, dfdv);
  // Symmetric form D K D with D = M^-1/2 (0 on pinned particles): same eigenvalues as M^-1 K on the free ones.
  VecX d(n);
  for (Eigen::Index i = 0; i < n; ++i) d[i] = std::sqrt(system.inverseMass()[i / 3]);
  Triplets k;
  k.reserve(dfdx.size());
  for (const auto& e : dfdx) k.emplace_back(e.row(), e.col(), -e.value() * d[e.row()] * d[e.col()]);
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(k.begin(), k.end());
  VecX y(n);
  for (Eigen::Index i = 0; i < n; ++i) y[i] = d[i] * (1 + 0.37 * std::sin(1.7 * double(i)));  // deterministic start
  if (y.norm() == 0) return 0;
  double lambda = 0;
  for (int it = 0; it < iterations; ++it) {
    y.normalize();
    VecX z = a * y;
    lambda = y.dot(z);
    if (z.norm() == 0) return 0;
    y = z;
  }
  return std::sqrt(std::max(0.0, lambda));
}

double damperRatio(const MassSpringSystem& system) {
  const Springs& s = system.springs();
  double r = kInf;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.ks[i] > 0) r = std::min(r, s.kd[i] / s.ks[i]);
  return std::isfinite(r) ? r : 0;
}

}  // namespace wobble
