#include "sim/pcg_kernels.h"

namespace wobble::pcg {
namespace {

// The lanes added pairwise, in one fixed order.
double sumLanes(const double* lane) {
  return ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
}

}  // namespace

// Clones for AVX-512, AVX2 and the baseline, compiled without FMA contraction (CMakeLists.txt): the lanes do the same
// operations in every clone, so every clone gives the same bits.
__attribute__((target_clones("avx512f", "avx2", "default"))) double dot(const double* __restrict a,
                                                                        const double* __restrict b, int n) {
  double lane[kSumLanes] = {};
  int j = 0;
  for (; j + kSumLanes <= n; j += kSumLanes)
    for (int l = 0; l < kSumLanes; ++l) lane[l] += a[j + l] * b[j + l];
  for (int l = 0; j < n; ++j, ++l) lane[l] += a[j] * b[j];
  return sumLanes(lane);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void scaleAdd(double* __restrict c,
                                                                           const double* __restrict q, double beta,
                                                                           int n) {
  for (int j = 0; j < n; ++j) c[j] = q[j] + beta * c[j];
}

__attribute__((target_clones("avx512f", "avx2", "default"))) double step(double* __restrict x, double* __restrict r,
                                                                         const double* __restrict c,
                                                                         const double* __restrict q, double alpha,
                                                                         int n) {
  double lane[kSumLanes] = {};
  int j = 0;
  for (; j + kSumLanes <= n; j += kSumLanes)
    for (int l = 0; l < kSumLanes; ++l) {
      x[j + l] += alpha * c[j + l];
      const double rj = r[j + l] - alpha * q[j + l];
      r[j + l] = rj;
      lane[l] += rj * rj;
    }
  for (int l = 0; j < n; ++j, ++l) {
    x[j] += alpha * c[j];
    r[j] -= alpha * q[j];
    lane[l] += r[j] * r[j];
  }
  return sumLanes(lane);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void blockProduct(const Sym3* __restrict m,
                                                                               const double* __restrict x,
                                                                               double* __restrict y, int particles) {
  for (int p = 0; p < particles; ++p) {
    const Sym3& b = m[p];
    const double x0 = x[3 * p], x1 = x[3 * p + 1], x2 = x[3 * p + 2];
    y[3 * p] = b.xx * x0 + b.xy * x1 + b.xz * x2;
    y[3 * p + 1] = b.xy * x0 + b.yy * x1 + b.yz * x2;
    y[3 * p + 2] = b.xz * x0 + b.yz * x1 + b.zz * x2;
  }
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void blockProductPlus(
    const Sym3* __restrict m, const double* __restrict r, const double* __restrict u, const int* __restrict aggregate,
    double* __restrict z, int particles) {
  for (int p = 0; p < particles; ++p) {
    const Sym3& b = m[p];
    const double* up = u + 3 * aggregate[p];
    const double r0 = r[3 * p], r1 = r[3 * p + 1], r2 = r[3 * p + 2];
    z[3 * p] = b.xx * r0 + b.xy * r1 + b.xz * r2 + up[0];
    z[3 * p + 1] = b.xy * r0 + b.yy * r1 + b.yz * r2 + up[1];
    z[3 * p + 2] = b.xz * r0 + b.yz * r1 + b.zz * r2 + up[2];
  }
}

}  // namespace wobble::pcg
