#include "sim/solver/pcg_kernels.h"

namespace wobble::pcg {
namespace {

// The lanes added pairwise, in one fixed order.
double sumLanes(const double* lane) {
  return ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
}

}  // namespace

// Clones for AVX-512, AVX2 and the baseline, compiled without FMA contraction (CMakeLists.txt): the lanes do the same
// operations in every clone, so every clone gives the same bits.
template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) double dot(const T* __restrict a, const T* __restrict b,
                                                                        int n) {
  double lane[kSumLanes] = {};
  int j = 0;
  for (; j + kSumLanes <= n; j += kSumLanes)
    for (int l = 0; l < kSumLanes; ++l) lane[l] += double(a[j + l]) * double(b[j + l]);
  for (int l = 0; j < n; ++j, ++l) lane[l] += double(a[j]) * double(b[j]);
  return sumLanes(lane);
}

template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) void scaleAdd(T* __restrict c, const T* __restrict q,
                                                                           double beta, int n) {
  const T b = T(beta);
  for (int j = 0; j < n; ++j) c[j] = q[j] + b * c[j];
}

template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) double step(T* __restrict x, T* __restrict r,
                                                                         const T* __restrict c, const T* __restrict q,
                                                                         double alpha, int n) {
  const T a = T(alpha);
  double lane[kSumLanes] = {};
  int j = 0;
  for (; j + kSumLanes <= n; j += kSumLanes)
    for (int l = 0; l < kSumLanes; ++l) {
      x[j + l] += a * c[j + l];
      const T rj = r[j + l] - a * q[j + l];
      r[j + l] = rj;
      lane[l] += double(rj) * double(rj);
    }
  for (int l = 0; j < n; ++j, ++l) {
    x[j] += a * c[j];
    r[j] -= a * q[j];
    lane[l] += double(r[j]) * double(r[j]);
  }
  return sumLanes(lane);
}

template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) void blockProduct(const T* __restrict m,
                                                                               const T* __restrict x, T* __restrict y,
                                                                               int particles) {
  for (int p = 0; p < particles; ++p) {
    const T* b = m + 6 * p;  // xx, yy, zz, xy, xz, yz
    const T x0 = x[3 * p], x1 = x[3 * p + 1], x2 = x[3 * p + 2];
    y[3 * p] = b[0] * x0 + b[3] * x1 + b[4] * x2;
    y[3 * p + 1] = b[3] * x0 + b[1] * x1 + b[5] * x2;
    y[3 * p + 2] = b[4] * x0 + b[5] * x1 + b[2] * x2;
  }
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void invertBlocks(const double* __restrict m,
                                                                               double* __restrict inverse,
                                                                               int particles) {
  for (int p = 0; p < particles; ++p) {
    const double* b = m + 6 * p;  // xx, yy, zz, xy, xz, yz
    const double xx = b[0], yy = b[1], zz = b[2], xy = b[3], xz = b[4], yz = b[5];
    const double c00 = yy * zz - yz * yz, c11 = xx * zz - xz * xz, c22 = xx * yy - xy * xy;
    const double c01 = xz * yz - xy * zz, c02 = xy * yz - xz * yy, c12 = xy * xz - xx * yz;
    const double r = 1.0 / (xx * c00 + xy * c01 + xz * c02);
    double* out = inverse + 6 * p;
    out[0] = c00 * r, out[1] = c11 * r, out[2] = c22 * r, out[3] = c01 * r, out[4] = c02 * r, out[5] = c12 * r;
  }
}

template <class T>
__attribute__((target_clones("avx512f", "avx2", "default"))) void blockProductPlus(const T* __restrict m,
                                                                                   const T* __restrict r,
                                                                                   const double* __restrict u,
                                                                                   const int* __restrict aggregate,
                                                                                   T* __restrict z, int particles) {
  for (int p = 0; p < particles; ++p) {
    const T* b = m + 6 * p;
    const double* up = u + 3 * aggregate[p];
    const T r0 = r[3 * p], r1 = r[3 * p + 1], r2 = r[3 * p + 2];
    z[3 * p] = b[0] * r0 + b[3] * r1 + b[4] * r2 + T(up[0]);
    z[3 * p + 1] = b[3] * r0 + b[1] * r1 + b[5] * r2 + T(up[1]);
    z[3 * p + 2] = b[4] * r0 + b[5] * r1 + b[2] * r2 + T(up[2]);
  }
}

template double dot(const double*, const double*, int);
template double dot(const float*, const float*, int);
template void scaleAdd(double*, const double*, double, int);
template void scaleAdd(float*, const float*, double, int);
template double step(double*, double*, const double*, const double*, double, int);
template double step(float*, float*, const float*, const float*, double, int);
template void blockProduct(const double*, const double*, double*, int);
template void blockProduct(const float*, const float*, float*, int);
template void blockProductPlus(const double*, const double*, const double*, const int*, double*, int);
template void blockProductPlus(const float*, const float*, const double*, const int*, float*, int);

}  // namespace wobble::pcg
