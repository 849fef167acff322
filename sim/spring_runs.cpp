#include "sim/spring_runs.h"

#include <algorithm>
#include <cmath>

namespace wobble {
namespace {

// The springs (xa + k, xb + k), k < length, with their rest lengths and coefficients from rest, ks, kd. fa and fb
// may overlap (a run whose offset is shorter than it): all of fa's adds come first, then fb's subtractions.
// Clones for AVX-512, AVX2 and the baseline, picked at load time; compiled without FMA contraction
// (CMakeLists.txt), so every clone gives the same bits.
__attribute__((target_clones("avx512f", "avx2", "default"))) void addRunForces(
    const double* __restrict xa, const double* __restrict xb, const double* __restrict va, const double* __restrict vb,
    const double* __restrict rest, const double* __restrict ks, const double* __restrict kd, int length, double* fa,
    double* fb) {
  constexpr int kChunk = 128;  // 3 KB a buffer: they stay in L1 between the passes
  alignas(64) double dx[3 * kChunk], dv[3 * kChunk], force[3 * kChunk];
  for (int c = 0; c < length; c += kChunk) {
    const int m = std::min(kChunk, length - c);
    const double *x0 = xa + 3 * c, *x1 = xb + 3 * c, *v0 = va + 3 * c, *v1 = vb + 3 * c;
    const double *r = rest + c, *s = ks + c, *d = kd + c;
    for (int j = 0; j < 3 * m; ++j) {  // contiguous: the differences before the per-spring work
      dx[j] = x0[j] - x1[j];
      dv[j] = v0[j] - v1[j];
    }
    for (int k = 0; k < m; ++k) {
      const double len =
          std::sqrt(dx[3 * k] * dx[3 * k] + dx[3 * k + 1] * dx[3 * k + 1] + dx[3 * k + 2] * dx[3 * k + 2]);
      const double inv = len > 0 ? 1.0 / len : 0.0;  // coincident endpoints: no direction, no force
      const double ux = dx[3 * k] * inv, uy = dx[3 * k + 1] * inv, uz = dx[3 * k + 2] * inv;
      const double speed = dv[3 * k] * ux + dv[3 * k + 1] * uy + dv[3 * k + 2] * uz;
      const double magnitude = -s[k] * (len - r[k]) - d[k] * speed;
      force[3 * k] = magnitude * ux;
      force[3 * k + 1] = magnitude * uy;
      force[3 * k + 2] = magnitude * uz;
    }
    double* a = fa + 3 * c;
    for (int j = 0; j < 3 * m; ++j) a[j] += force[j];
    double* b = fb + 3 * c;
    for (int j = 0; j < 3 * m; ++j) b[j] -= force[j];
  }
}

}  // namespace

void addSpringForces(const Springs& s, std::span<const PairRun> runs, const VecX& x, const VecX& v, VecX& f) {
  const double *xs = x.data(), *vs = v.data();
  double* fs = f.data();
  splitRuns(
      runs,
      [&](const PairRun& run) {
        const int a = 3 * run.a, b = 3 * (run.a + run.offset), e = run.first;
        addRunForces(xs + a, xs + b, vs + a, vs + b, s.rest.data() + e, s.ks.data() + e, s.kd.data() + e, run.length,
                     fs + a, fs + b);
      },
      [&](int begin, int end) { addSpringForces(s, begin, end, x, v, f); });
}

}  // namespace wobble
