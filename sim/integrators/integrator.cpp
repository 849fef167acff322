#include "integrator.h"

#include <array>
#include <stdexcept>

#include "methods.h"

namespace wobble {
namespace {

struct Method {
  std::string_view name;
  std::unique_ptr<Integrator> (*make)(const IntegratorOptions&);
};

constexpr std::array kMethods{
    Method{"explicit-euler", makeExplicitEuler},
    Method{"symplectic-euler", makeSymplecticEuler},
    Method{"pc-euler", makePcEuler},
    Method{"midpoint", makeMidpoint},
    Method{"rk4", makeRk4},
    Method{"rk45", makeRk45},
    Method{"backward-euler", makeBackwardEuler},
};

constexpr auto kNames = [] {
  std::array<std::string_view, kMethods.size()> names{};
  for (std::size_t i = 0; i < kMethods.size(); ++i) names[i] = kMethods[i].name;
  return names;
}();

}  // namespace

std::span<const std::string_view> integratorNames() { return kNames; }

std::unique_ptr<Integrator> makeIntegrator(std::string_view name, const IntegratorOptions& options) {
  for (const Method& m : kMethods)
    if (m.name == name) return m.make(options);
  std::string allowed;
  for (std::string_view n : kNames) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  throw std::invalid_argument("unknown integrator '" + std::string(name) + "' (allowed: " + allowed + ")");
}

}  // namespace wobble
