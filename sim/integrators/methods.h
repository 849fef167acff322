// Constructors of the integration methods, one per file in this folder; integrator.cpp maps names to them.
#pragma once
#include "sim/integrators/integrator.h"

namespace wobble {

std::unique_ptr<Integrator> makeExplicitEuler(const IntegratorOptions&);
std::unique_ptr<Integrator> makePcEuler(const IntegratorOptions&);
std::unique_ptr<Integrator> makeMidpoint(const IntegratorOptions&);
std::unique_ptr<Integrator> makeRk4(const IntegratorOptions&);
std::unique_ptr<Integrator> makeSymplecticEuler(const IntegratorOptions&);
std::unique_ptr<Integrator> makeRk45(const IntegratorOptions&);
std::unique_ptr<Integrator> makeBackwardEuler(const IntegratorOptions&);

}  // namespace wobble
