#include "sim/integrators/integrator.h"

#include <array>
#include <stdexcept>

#include "sim/integrators/methods.h"

namespace wobble {
namespace {

struct Method {
  std::string_view name;
  std::unique_ptr<Integrator> (*make)(const IntegratorOptions&);
  IntegratorTraits traits;
};

// One row per method: adding a method is a file in this folder, its constructor in methods.h and a row here.
constexpr std::array kMethods{
    Method{"explicit-euler", makeExplicitEuler, {.order = 1}},
    Method{"symplectic-euler", makeSymplecticEuler, {.order = 1}},
    Method{"pc-euler", makePcEuler, {.order = 1}},
    Method{"midpoint", makeMidpoint, {.order = 2}},
    Method{"rk4", makeRk4, {.order = 4, .contact_in_stages = true}},
    Method{"rk45", makeRk45, {.order = 5, .adaptive = true}},
    Method{"backward-euler",
           makeBackwardEuler,
           {.order = 1, .a_stable = true, .implicit = true, .body_contact_in_solve = true}},
};

static_assert(
    [] {
      for (const Method& m : kMethods)
        if (m.traits.order < 1) return false;
      return true;
    }(),
    "every method in kMethods states its order of accuracy (IntegratorTraits::order >= 1)");

constexpr auto kNames = [] {
  std::array<std::string_view, kMethods.size()> names{};
  for (std::size_t i = 0; i < kMethods.size(); ++i) names[i] = kMethods[i].name;
  return names;
}();

const Method& method(std::string_view name) {
  for (const Method& m : kMethods)
    if (m.name == name) return m;
  std::string allowed;
  for (std::string_view n : kNames) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  throw std::invalid_argument("unknown integrator '" + std::string(name) + "' (allowed: " + allowed + ")");
}

}  // namespace

std::span<const std::string_view> integratorNames() { return kNames; }

const IntegratorTraits& integratorTraits(std::string_view name) { return method(name).traits; }

std::unique_ptr<Integrator> makeIntegrator(std::string_view name, const IntegratorOptions& options) {
  return method(name).make(options);
}

}  // namespace wobble
