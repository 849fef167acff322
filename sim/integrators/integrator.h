// A time integrator advances (x, v) by one step of a Dynamics. Integrators know nothing about particles,
// springs or contacts; they may only call Dynamics::acceleration, and write x and v once, at the step's end.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "../dynamics.h"

namespace wobble {

// Settings that only some methods read (adaptive and implicit ones); the defaults suit the shipped scenes.
struct IntegratorOptions {
  double rtol = 1e-6, atol = 1e-9;  // rk45: relative and absolute error tolerances per step
  bool newton = false;              // backward-euler: iterate Newton to convergence instead of one step
  double cg_tolerance = 1e-6;       // backward-euler: relative residual of the conjugate-gradient solve
  int cg_max_iterations = 1000;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual std::string_view name() const = 0;
  // Advances x, v from time t to t + h.
  virtual void step(const Dynamics& dynamics, double t, double h, VecX& x, VecX& v) = 0;
};

// The names makeIntegrator accepts, in the order the docs list them.
std::span<const std::string_view> integratorNames();
// Throws std::invalid_argument naming the allowed values when name is unknown.
std::unique_ptr<Integrator> makeIntegrator(std::string_view name, const IntegratorOptions& options = {});

}  // namespace wobble
