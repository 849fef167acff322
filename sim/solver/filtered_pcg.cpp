#include "sim/solver/filtered_pcg.h"

#include "sim/solver/pcg_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wobble {
namespace {

// Stores a symmetric block as 6 values (pcg_kernels.h).
template <class T>
void storeBlock(const Sym3& m, T* out) {
  out[0] = T(m.xx), out[1] = T(m.yy), out[2] = T(m.zz), out[3] = T(m.xy), out[4] = T(m.xz), out[5] = T(m.yz);
}

PcgSystemTap system_tap = nullptr;

}  // namespace

void setPcgSystemTap(PcgSystemTap tap) { system_tap = tap; }

void FilteredPcg::setUpPreconditioner(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel) {
  a.diagonal(diagonal_, parallel);
  const int n = static_cast<int>(diagonal_.size());
  double_.inverse.resize(6 * std::size_t(n));
  forEachChunk(n, parallel, [&](int begin, int end) {
    // Every block inverted as a free particle's in one vectorised pass, then the filtered ones replaced.
    pcg::invertBlocks(&diagonal_[begin].xx, double_.inverse.data() + 6 * begin, end - begin);
    for (int p = begin; p < end; ++p) {
      if (s.kind(p) == ParticleFilter::Free) continue;
      Sym3 inverse;  // held: 0
      if (s.kind(p) == ParticleFilter::Normal) {
        // The filtered block S D S + n n^T, inverted; S applied after it keeps only its tangential part.
        const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - Sym3::outer(s.normal(p)).dense();
        const Eigen::Matrix3d filtered = proj * diagonal_[p].dense() * proj + Sym3::outer(s.normal(p)).dense();
        inverse = Sym3::fromDense(proj * filtered.inverse() * proj);
      } else if (s.kind(p) == ParticleFilter::Line) {
        // S (S D S + I - S)^-1 S with S = d d^T: S D S = (d . D d) S, so the inverse on the line is S / (d . D d).
        const Vec3 d = s.direction(p);
        inverse = (1 / d.dot(diagonal_[p] * d)) * Sym3::outer(d);
      }
      storeBlock(inverse, double_.inverse.data() + 6 * p);
    }
  });
}

double FilteredPcg::residual(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, const VecX& x,
                             bool parallel) {
  const int n = static_cast<int>(b.size() / 3);
  a.multiply(x, q_, parallel);
  r_.resize(b.size());
  return sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) particle(r_, p) = s.apply(p, particle(b, p) - particle(q_, p));
    return pcg::dot(r_.data() + 3 * begin, r_.data() + 3 * begin, 3 * (end - begin));
  });
}

template <class T, class Matrix>
int FilteredPcg::iterate(const Matrix& a, const ParticleFilter& s, T* xs, T* rs, Iterates<T>& it, double& r_norm2,
                         double threshold, int max_iterations, bool parallel, bool two_level) {
  const int n = static_cast<int>(it.inverse.size() / 6);  // it.c and it.q are sized by solve()
  // S y on the constrained particles of chunk [begin, end) (the vector loops run over plain arrays and fix these
  // after).
  const auto filterChunk = [&](T* y, int begin, int end) {
    const auto first = std::lower_bound(constrained_.begin(), constrained_.end(), begin);
    for (auto i = first; i != constrained_.end() && *i < end; ++i) {
      T* yp = y + 3 * *i;
      const Vec3 f = s.apply(*i, Vec3(yp[0], yp[1], yp[2]));
      yp[0] = T(f.x()), yp[1] = T(f.y()), yp[2] = T(f.z());
    }
  };
  T *cs = it.c.data(), *qs = it.q.data();
  const T* inverse = it.inverse.data();
  // z = P^-1 r into z (filtered), after the coarse solve when two-level; returns r.z.
  const auto precondition = [&](T* z) {
    if (two_level) coarse_.solve(rs, parallel);
    return sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      const int m = end - begin;
      if (two_level)
        pcg::blockProductPlus(inverse + 6 * begin, rs + 3 * begin, coarse_.corrections(), coarse_.aggregates() + begin,
                              z + 3 * begin, m);
      else pcg::blockProduct(inverse + 6 * begin, rs + 3 * begin, z + 3 * begin, m);
      if (two_level) filterChunk(z, begin, end);  // S u; block-Jacobi's inverse is filtered already
      return pcg::dot(rs + 3 * begin, z + 3 * begin, 3 * m);
    });
  };

  double delta = precondition(cs), beta = 0;
  int iterations = 0;
  while (r_norm2 >= threshold && iterations < max_iterations) {
    // q = A c in one pass, with the direction's update c = z + beta c (z in q) fused into it block by block.
    multiplyFused(a, cs, qs, parallel, [&](int begin, int end) {
      if (iterations > 0) pcg::scaleAdd(cs + 3 * begin, qs + 3 * begin, beta, 3 * (end - begin));
    });
    ++iterations;
    // q = S A c, alpha = delta / c.q
    const double cq = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      filterChunk(qs, begin, end);
      return pcg::dot(cs + 3 * begin, qs + 3 * begin, 3 * (end - begin));
    });
    const double alpha = delta / cq;
    // x += alpha c, r -= alpha q; the next preconditioned residual z = P^-1 r (into q: it is free until the next
    // product) and its products.
    r_norm2 = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      const int i = 3 * begin;
      return pcg::step(xs + i, rs + i, cs + i, qs + i, alpha, 3 * (end - begin));
    });
    const double rz = precondition(qs);
    beta = rz / delta;
    delta = rz;
  }
  return iterations;
}

PcgResult FilteredPcg::solve(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, VecX& x,
                             double tolerance, int max_iterations, bool parallel, bool two_level,
                             double absolute_tolerance) {
  if (system_tap) system_tap(a, s, b, x, tolerance);
  const int n = static_cast<int>(b.size() / 3);
  bool set_up_coarse = false;
  if (!two_level) {
    coarse_uses_ = 0;
  } else {
    set_up_coarse = coarse_uses_ == 0 || coarse_uses_ >= kCoarseRefresh || !coarse_.fits(a) ||
                    a.stencils().generation() != coarse_stencils_ || s.kinds() != coarse_kinds_;
    if (set_up_coarse) coarse_stencils_ = a.stencils().generation(), coarse_kinds_ = s.kinds();
    coarse_uses_ = set_up_coarse ? 1 : coarse_uses_ + 1;
  }
  const bool single = tolerance >= kSingleTolerance && single_pays_;
  // Every buffer sized on every solve, whichever precision runs: a switch of precision allocates nothing.
  single_matrix_.reserve(a);
  for (std::vector<float>* v : {&single_.x, &single_.r, &single_.c, &single_.q}) v->resize(b.size());
  for (std::vector<double>* v : {&double_.c, &double_.q}) v->resize(b.size());
  single_.inverse.resize(2 * b.size());
  // The fine level's setup: block-Jacobi, the filtered right-hand side's norm S (b - A z) with z = (I - S) x (only
  // contacts make z nonzero), the residual r = S (b - A x), and for float iterations the matrix's float copy.
  double b_norm2 = 0, r_norm2 = 0, threshold = 0;
  const auto setUpFine = [&] {
    setUpPreconditioner(a, s, parallel);
    z_.resize(b.size());  // sized on every solve: a step that meets its first contact allocates nothing
    if (s.anyConstrained()) {
      forEachChunk(n, parallel, [&](int begin, int end) {
        for (int p = begin; p < end; ++p) particle(z_, p) = s.removed(p, particle(x, p));
      });
      b_norm2 = residual(a, s, b, z_, parallel);
    } else {
      b_norm2 = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
        double sum = 0;
        for (int p = begin; p < end; ++p) sum += s.apply(p, particle(b, p)).squaredNorm();
        return sum;
      });
    }
    if (b_norm2 == 0) return;
    // As Eigen's CG: a residual below the smallest normal double counts as 0 (a state decaying into denormals would
    // otherwise divide 0 by 0).
    threshold = std::max(
        {tolerance * tolerance * b_norm2, absolute_tolerance * absolute_tolerance, std::numeric_limits<double>::min()});
    r_norm2 = residual(a, s, b, x, parallel);
    if (single && r_norm2 >= threshold) {  // float rounds will run
      single_matrix_.assign(a, parallel);
      single_.inverse.assign(double_.inverse.begin(), double_.inverse.end());
    }
  };
  // The coarse level's setup (its fill and factorization run on one thread) at the same time as the fine level's.
  runBoth(
      parallel && set_up_coarse, [&] { setUpFine(); },
      [&] {
        if (set_up_coarse) coarse_.setUp(a, s, parallel);
      });
  if (b_norm2 == 0) {  // the free part's solution is 0
    r_.setZero(b.size());
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) particle(x, p) = s.removed(p, particle(x, p));
    });
    return {};
  }
  const bool by_absolute = absolute_tolerance * absolute_tolerance > tolerance * tolerance * b_norm2;
  constrained_.reserve(n);
  constrained_.clear();
  for (int p = 0; p < n; ++p)
    if (s.kind(p) != ParticleFilter::Free) constrained_.push_back(p);

  PcgResult result;
  if (!single) {
    result.iterations =
        iterate(a, s, x.data(), r_.data(), double_, r_norm2, threshold, max_iterations, parallel, two_level);
  } else {
    while (r_norm2 >= threshold && result.iterations < max_iterations) {
      // A e = r in float, r scaled by a power of two to a largest entry near 1 (float's range is narrow; a power of
      // two scales exactly), to the threshold on the same scale; then x += e and r again in double.
      int exponent = 0;
      std::frexp(r_.cwiseAbs().maxCoeff(), &exponent);
      const double scale = std::ldexp(1.0, -exponent);
      forEachChunk(n, parallel, [&](int begin, int end) {
        std::fill(single_.x.begin() + 3 * begin, single_.x.begin() + 3 * end, 0.0f);
        for (int j = 3 * begin; j < 3 * end; ++j) single_.r[j] = static_cast<float>(scale * r_[j]);
      });
      double round_norm2 = scale * scale * r_norm2;
      result.iterations += iterate(single_matrix_, s, single_.x.data(), single_.r.data(), single_, round_norm2,
                                   scale * scale * threshold, max_iterations - result.iterations, parallel, two_level);
      ++result.rounds;
      // x += e, filtered again in double on the constrained particles: float's S e keeps a trace (1e-8) of the
      // normal part, which must stay as prescribed.
      forEachChunk(n, parallel, [&](int begin, int end) {
        for (int p = begin; p < end; ++p) {
          const Vec3 e(single_.x[3 * p], single_.x[3 * p + 1], single_.x[3 * p + 2]);
          particle(x, p) += s.apply(p, e / scale);
        }
      });
      r_norm2 = residual(a, s, b, x, parallel);
    }
  }
  single_pays_ = result.iterations >= kSingleIterations;
  result.by_absolute = by_absolute;
  result.relative_residual = std::sqrt(r_norm2 / b_norm2);
  return result;
}

}  // namespace wobble
