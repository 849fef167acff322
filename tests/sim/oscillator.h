// Test fixture shared by the numerics tests: a linear oscillator built from the simulator's own parts.
// Particle 0 is pinned at the origin, particle 1 (mass m) hangs on a spring of rest length 1 along x, no gravity.
// Motion stays on the x axis, where the spring and damper forces are exactly linear: m x'' = -k x - c x', with
// x the spring's stretch. So the analytic damped oscillator is an independent oracle for any integrator.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble::testing {

struct OscillatorState {
  double x = 0, v = 0;  // stretch and its rate
};

// Spring constants for natural frequency omega and damping ratio zeta with particle mass m.
inline std::unique_ptr<MassSpringSystem> makeOscillator(double omega, double zeta, double m = 1) {
  Body body;
  body.name = "oscillator";
  body.kind = "test";
  body.x = VecX::Zero(6);
  body.x[3] = 1;
  body.v = VecX::Zero(6);
  body.mass = VecX::Constant(2, m);
  body.pinned = {true, false};
  body.springs.add(0, 1, 1.0, m * omega * omega, 2 * zeta * omega * m, SpringType::Structural);
  auto system = std::make_unique<MassSpringSystem>(Vec3::Zero());
  system->addBody(std::move(body));
  return system;
}

inline void setOscillatorState(OscillatorState s, VecX& x, VecX& v) {
  x = VecX::Zero(6);
  v = VecX::Zero(6);
  x[3] = 1 + s.x;
  v[3] = s.v;
}

inline OscillatorState oscillatorState(const VecX& x, const VecX& v) { return {x[3] - 1, v[3]}; }

// x(t) = exp(-zeta w t) [x0 cos(wd t) + (v0 + zeta w x0)/wd sin(wd t)], wd = w sqrt(1 - zeta^2), and its derivative.
inline OscillatorState dampedOscillator(double w, double zeta, OscillatorState s0, double t) {
  const double wd = w * std::sqrt(1 - zeta * zeta), decay = std::exp(-zeta * w * t);
  const double c = std::cos(wd * t), s = std::sin(wd * t);
  return {decay * (s0.x * c + (s0.v + zeta * w * s0.x) / wd * s),
          decay * (s0.v * c - (zeta * w * s0.v + w * w * s0.x) / wd * s)};
}

// Fixed steps of h from s0 with the named method; returns the final state.
inline OscillatorState runOscillator(Integrator& integrator, const MassSpringSystem& system, OscillatorState s0,
                                     double h, long steps) {
  VecX x, v;
  setOscillatorState(s0, x, v);
  for (long i = 0; i < steps; ++i) integrator.step(system, i * h, h, x, v);
  return oscillatorState(x, v);
}

// Least-squares slope of log(error) against log(h): the observed convergence order.
inline double fittedOrder(const std::vector<double>& h, const std::vector<double>& error) {
  const std::size_t n = h.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double lx = std::log(h[i]), ly = std::log(error[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace wobble::testing
