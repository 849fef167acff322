// Where theory puts the stability boundary of each integrator on a mass-spring system (docs/numerics.md):
//  - omega_max, the fastest mode: bounded by Gershgorin, omega_max^2 <= max_i 2 sum_j k_ij / m_i over free
//    particles, or estimated by power iteration on M^-1 K at the initial state (K = -dF/dx: springs only);
//  - a mode of frequency w with dampers along the springs (damping matrix (kd/ks) K) has damping ratio
//    zeta = (kd/ks) w / 2, and a method is stable on it while w h stays below its limit at that zeta;
//  - the largest stable step is the smallest of limit(zeta(w)) / w over the modes, taken over w in
//    [omega_max / 100, omega_max].
// The limit of w h is measured on the method's own one-step map: the integrator steps a linear oscillator
// (one free particle on a spring along its axis, where the force is exactly linear) from two unit states, and the
// 2 x 2 map is stable while its spectral radius is <= 1. An adaptive method (rk45) chooses its own step, so it has
// no fixed-step limit (+inf), as has an A-stable one (backward Euler): IntegratorTraits in the method table.
#pragma once
#include <string_view>

#include "sim/system.h"

namespace wobble {

// Largest stable omega h of a fixed-step method on a linear oscillator with damping ratio zeta (+inf if none).
double stableOmegaH(std::string_view integrator, double zeta);

// Largest stable step on modes up to omega_max with dampers in ratio kd/ks = r.
double stableStep(std::string_view integrator, double omega_max, double r);

double gershgorinOmegaMax(const MassSpringSystem& system);
double powerIterationOmegaMax(const MassSpringSystem& system, int iterations = 300);

// The smallest kd/ks over springs with ks > 0 (the least damped), 0 if none.
double damperRatio(const MassSpringSystem& system);

}  // namespace wobble
