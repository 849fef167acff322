// What an integrator sees of a physical system: accelerations as a function of time and flat state.
#pragma once
#include "types.h"

namespace wobble {

class Dynamics {
 public:
  virtual ~Dynamics() = default;
  // a = M^-1 f(t, x, v). Must be a pure function of its arguments: integrators call it at trial states.
  virtual void acceleration(double t, const VecX& x, const VecX& v, VecX& a) const = 0;
};

}  // namespace wobble
