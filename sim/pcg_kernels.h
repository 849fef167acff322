// The conjugate gradients' vector loops (filtered_pcg.h) as kernels over plain arrays of doubles that the compiler
// vectorises: elementwise updates, 3x3 symmetric block products and dot products. A dot product sums into a fixed
// number of lanes (element j into lane j mod kSumLanes) and then adds the lanes in a fixed order, so that its bits
// depend on the array's length alone, not on the vector width of the machine nor on the thread count.
#pragma once
#include "sim/sym3.h"

namespace wobble::pcg {

inline constexpr int kSumLanes = 8;

// sum of a[j] b[j], j < n.
double dot(const double* a, const double* b, int n);
// c = q + beta c.
void scaleAdd(double* c, const double* q, double beta, int n);
// x += alpha c, r -= alpha q; returns sum of r[j]^2 (the new r).
double step(double* x, double* r, const double* c, const double* q, double alpha, int n);
// y = m[p] x_p for particles p < particles (x, y: 3 values a particle).
void blockProduct(const Sym3* m, const double* x, double* y, int particles);
// z = m[p] r_p + u[aggregate[p]] for particles p < particles (u: 3 values per aggregate).
void blockProductPlus(const Sym3* m, const double* r, const double* u, const int* aggregate, double* z, int particles);

}  // namespace wobble::pcg
