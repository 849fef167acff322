// The conjugate gradients' vector loops (filtered_pcg.h) as kernels over plain arrays that the compiler vectorises:
// elementwise updates, 3x3 symmetric block products and dot products, for T = double (the solve) and float (its inner
// iterations). A dot product sums into a fixed number of double lanes (element j into lane j mod kSumLanes) and then
// adds the lanes in a fixed order, so that its bits depend on the array's length alone, not on the vector width of the
// machine nor on the thread count.
#pragma once

namespace wobble::pcg {

inline constexpr int kSumLanes = 8;

// sum of a[j] b[j], j < n.
template <class T>
double dot(const T* a, const T* b, int n);
// c = q + beta c.
template <class T>
void scaleAdd(T* c, const T* q, double beta, int n);
// x += alpha c, r -= alpha q; returns sum of r[j]^2 (the new r).
template <class T>
double step(T* x, T* r, const T* c, const T* q, double alpha, int n);
// y = m_p x_p for particles p < particles (x, y: 3 values a particle; m: 6 a particle, a symmetric block's xx, yy,
// zz, xy, xz, yz as in Sym3).
template <class T>
void blockProduct(const T* m, const T* x, T* y, int particles);
// inverse_p = m_p^-1 for particles p < particles (6 values a particle, as blockProduct's m), by the symmetric
// cofactors: the blocks must be invertible (block-Jacobi's free particles: their blocks are at least the mass).
void invertBlocks(const double* m, double* inverse, int particles);
// z = m_p r_p + u[aggregate[p]] for particles p < particles (u: 3 values per aggregate).
template <class T>
void blockProductPlus(const T* m, const T* r, const double* u, const int* aggregate, T* z, int particles);

}  // namespace wobble::pcg
