#include "sim/spring_runs.h"

#include "sim/force_jacobian.h"

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

// The Jacobian blocks of the springs (xa + k, xb + k), k < length (force_jacobian.h): blocks[k] = cx Kx + cv Kv as
// a I + w w^T in the four columns from their first pair on; with wa, wb (not null), u = Kx (wa[k] - wb[k]) is
// subtracted from kwa[k] and added to kwb[k] (all of kwa's first, as the forces). The same clones and bits rule as
// addRunForces.
__attribute__((target_clones("avx512f", "avx2", "default"))) void fillRunBlocks(
    const double* __restrict xa, const double* __restrict xb, const double* __restrict rest,
    const double* __restrict ks, const double* __restrict kd, int length, double cx, double cv,
    const PairBlockColumns blocks, const double* __restrict wa, const double* __restrict wb, double* kwa, double* kwb) {
  constexpr int kChunk = 128;
  alignas(64) double dx[3 * kChunk], dw[3 * kChunk], u[3 * kChunk];
  alignas(64) double across_k[kChunk], along_k[kChunk], dir[3 * kChunk];  // Kx = across I + along d d^T
  for (int c = 0; c < length; c += kChunk) {
    const int m = std::min(kChunk, length - c);
    const double *x0 = xa + 3 * c, *x1 = xb + 3 * c, *r = rest + c, *s = ks + c, *d = kd + c;
    double* __restrict ba = blocks.v[0] + c;
    double* __restrict bwx = blocks.v[1] + c;
    double* __restrict bwy = blocks.v[2] + c;
    double* __restrict bwz = blocks.v[3] + c;
    for (int j = 0; j < 3 * m; ++j) dx[j] = x0[j] - x1[j];
    for (int k = 0; k < m; ++k) {
      const double len =
          std::sqrt(dx[3 * k] * dx[3 * k] + dx[3 * k + 1] * dx[3 * k + 1] + dx[3 * k + 2] * dx[3 * k + 2]);
      // Coincident endpoints: no direction, no force, no derivative (every block value 0).
      const double inv = len > 0 ? 1.0 / len : 0.0, live = len > 0 ? 1.0 : 0.0;
      const double ux = dx[3 * k] * inv, uy = dx[3 * k + 1] * inv, uz = dx[3 * k + 2] * inv;
      const double transverse = std::max(0.0, 1.0 - r[k] * inv);
      // Kx = across I + along d d^T; cx Kx + cv Kv = (cx across) I + (cx along + cv kd) d d^T, stored as a I + w w^T
      // (force_jacobian.h); Kx's two coefficients and d are kept for Kx dw below.
      const double along = s[k] * (1.0 - transverse), across = live * (s[k] * transverse);
      const double root = std::sqrt(cx * along + cv * d[k]);
      ba[k] = cx * across;
      bwx[k] = root * ux;
      bwy[k] = root * uy;
      bwz[k] = root * uz;
      across_k[k] = across;
      along_k[k] = along;
      dir[3 * k] = ux, dir[3 * k + 1] = uy, dir[3 * k + 2] = uz;
    }
    if (!wa) continue;
    for (int j = 0; j < 3 * m; ++j) dw[j] = wa[3 * c + j] - wb[3 * c + j];
    for (int k = 0; k < m; ++k) {  // u = Kx dw, Kx = across I + along d d^T (no square root of along needed)
      const double t =
          along_k[k] * (dir[3 * k] * dw[3 * k] + dir[3 * k + 1] * dw[3 * k + 1] + dir[3 * k + 2] * dw[3 * k + 2]);
      for (int i = 0; i < 3; ++i) u[3 * k + i] = across_k[k] * dw[3 * k + i] + t * dir[3 * k + i];
    }
    double* a = kwa + 3 * c;
    for (int j = 0; j < 3 * m; ++j) a[j] -= u[j];
    double* b = kwb + 3 * c;
    for (int j = 0; j < 3 * m; ++j) b[j] += u[j];
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

namespace wobble {

void fillSpringBlocks(const Springs& s, std::span<const PairRun> runs, const VecX& x, double cx, double cv,
                      PairBlockColumns blocks, const VecX* w, VecX* kw) {
  const double* xs = x.data();
  splitRuns(
      runs,
      [&](const PairRun& run) {
        const int a = 3 * run.a, b = 3 * (run.a + run.offset), e = run.first;
        fillRunBlocks(xs + a, xs + b, s.rest.data() + e, s.ks.data() + e, s.kd.data() + e, run.length, cx, cv,
                      blocks.shifted(e), w ? w->data() + a : nullptr, w ? w->data() + b : nullptr,
                      kw ? kw->data() + a : nullptr, kw ? kw->data() + b : nullptr);
      },
      [&](int begin, int end) { fillSpringBlocks(s, begin, end, x, cx, cv, blocks, w, kw); });
}

}  // namespace wobble
