// Jacobians of the spring, damper and air-drag forces, for implicit integrators (Baraff & Witkin 1998).
#pragma once
#include "sim/dynamics.h"
#include "sim/springs.h"
#include "sim/solver/sym3.h"

namespace wobble {

// Appends the spring and damper blocks. For a spring with unit direction d = (xa - xb)/l:
//   dFa/dxa = -ks [d d^T + max(0, 1 - rest/l) (I - d d^T)]   (the clamp keeps compressed springs from making the
//                                                             system indefinite; CG needs it positive definite)
//   dFa/dva = -kd d d^T                                        (the damper's dependence on x is dropped, as B&W do:
//                                                             it is not symmetric)
// and dFa/dxb = -dFa/dxa, dFb/dxb = dFa/dxa (same for v).
void addSpringJacobians(const Springs& s, const VecX& x, Triplets& dfdx, Triplets& dfdv);

// Appends dF/dv = -drag_i I for each particle i (viscous air drag f = -drag v).
void addDragJacobian(const VecX& drag, Triplets& dfdv);

// The same spring blocks on the fixed pattern, for springs [begin, end): blocks[i] = cx Kx + cv Kv with
// Kx = -dFa/dxa, Kv = -dFa/dva of spring i, stored as a I + w w^T (cx, cv, ks, kd >= 0): Kx = ks (t I + (1 - t) d d^T)
// with t = max(0, 1 - rest / length) and Kv = kd d d^T, so a = cx ks t and w = sqrt(cx ks (1 - t) + cv kd) d. With w,
// also kw += dF/dx w (kw's a and b entries of each spring).
void fillSpringBlocks(const Springs& s, int begin, int end, const VecX& x, double cx, double cv,
                      PairBlockColumns blocks, const VecX* w, VecX* kw);

}  // namespace wobble
