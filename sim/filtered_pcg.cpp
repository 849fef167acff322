#include "sim/filtered_pcg.h"

#include "sim/pcg_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wobble {

void FilteredPcg::setUpPreconditioner(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel) {
  a.diagonal(diagonal_, parallel);
  inverse_.resize(diagonal_.size());
  forEachChunk(static_cast<int>(diagonal_.size()), parallel, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      switch (s.kind(p)) {
        case ParticleFilter::Free:
          inverse_[p] = Sym3::fromDense(diagonal_[p].dense().inverse());
          break;
        case ParticleFilter::Held:
          inverse_[p] = Sym3{};
          break;
        case ParticleFilter::Normal: {
          // The filtered block S D S + n n^T, inverted; S applied after it keeps only its tangential part.
          const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - Sym3::outer(s.normal(p)).dense();
          const Eigen::Matrix3d filtered = proj * diagonal_[p].dense() * proj + Sym3::outer(s.normal(p)).dense();
          inverse_[p] = Sym3::fromDense(proj * filtered.inverse() * proj);
        }
      }
    }
  });
}

PcgResult FilteredPcg::solve(const PairBlockMatrix& a, const ParticleFilter& s, const VecX& b, VecX& x,
                             double tolerance, int max_iterations, bool parallel, bool two_level) {
  const int n = static_cast<int>(b.size() / 3);
  setUpPreconditioner(a, s, parallel);
  if (!two_level) {
    coarse_uses_ = 0;
  } else {
    if (coarse_uses_ == 0 || coarse_uses_ >= kCoarseRefresh || !coarse_.fits(a)) {
      coarse_.setUp(a, s);
      coarse_uses_ = 0;
    }
    ++coarse_uses_;
  }
  r_.resize(b.size());
  c_.resize(b.size());
  q_.resize(b.size());
  z_.resize(b.size());
  // The filtered right-hand side's norm, S (b - A z) with z = (I - S) x: only contacts make z nonzero.
  double b_norm2 = 0;
  const auto filteredResidualNorm2 = [&](const VecX& y) {
    a.multiply(y, q_, parallel);
    return sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      double sum = 0;
      for (int p = begin; p < end; ++p) sum += s.apply(p, particle(b, p) - particle(q_, p)).squaredNorm();
      return sum;
    });
  };
  if (s.anyConstrained()) {
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) particle(z_, p) = s.removed(p, particle(x, p));
    });
    b_norm2 = filteredResidualNorm2(z_);
  } else {
    b_norm2 = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      double sum = 0;
      for (int p = begin; p < end; ++p) sum += s.apply(p, particle(b, p)).squaredNorm();
      return sum;
    });
  }
  if (b_norm2 == 0) {  // the free part's solution is 0
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int p = begin; p < end; ++p) particle(x, p) = s.removed(p, particle(x, p));
    });
    return {};
  }
  // As Eigen's CG: a residual below the smallest normal double counts as 0 (a state decaying into denormals would
  // otherwise divide 0 by 0).
  const double threshold = std::max(tolerance * tolerance * b_norm2, std::numeric_limits<double>::min());

  // The particles S does not leave alone, in order: the vector loops run over plain arrays and fix these after.
  constrained_.reserve(n);
  constrained_.clear();
  for (int p = 0; p < n; ++p)
    if (s.kind(p) != ParticleFilter::Free) constrained_.push_back(p);
  const auto filterChunk = [&](VecX& y, int begin, int end) {
    const auto first = std::lower_bound(constrained_.begin(), constrained_.end(), begin);
    for (auto it = first; it != constrained_.end() && *it < end; ++it)
      particle(y, *it) = s.apply(*it, particle(y, *it));
  };
  double *xs = x.data(), *rs = r_.data(), *cs = c_.data(), *qs = q_.data();
  const Sym3* inverse = inverse_.data();
  // z = P^-1 r into z (filtered), after the coarse solve when two-level; returns r.z.
  const auto precondition = [&](double* z) {
    if (two_level) coarse_.solve(r_, parallel);
    return sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      const int m = end - begin;
      if (two_level)
        pcg::blockProductPlus(inverse + begin, rs + 3 * begin, coarse_.corrections(), coarse_.aggregates() + begin,
                              z + 3 * begin, m);
      else pcg::blockProduct(inverse + begin, rs + 3 * begin, z + 3 * begin, m);
      if (two_level) filterChunk(z == cs ? c_ : q_, begin, end);  // S u; block-Jacobi's inverse is filtered already
      return pcg::dot(rs + 3 * begin, z + 3 * begin, 3 * m);
    });
  };

  // r = S (b - A x), c = P^-1 r (filtered), delta = r.c; |r|^2 alongside.
  a.multiply(x, q_, parallel);
  double r_norm2 = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) particle(r_, p) = s.apply(p, particle(b, p) - particle(q_, p));
    return pcg::dot(rs + 3 * begin, rs + 3 * begin, 3 * (end - begin));
  });
  double delta = precondition(cs), beta = 0;
  PcgResult result;
  while (r_norm2 >= threshold && result.iterations < max_iterations) {
    // q = A c, with the direction's update c = z + beta c (z in q) fused into the diagonal part of the product.
    if (result.iterations++ == 0) {
      a.multiply(c_, q_, parallel);
    } else {
      forEachChunk(n, parallel, [&](int begin, int end) {
        pcg::scaleAdd(cs + 3 * begin, qs + 3 * begin, beta, 3 * (end - begin));
        a.multiplySelf(c_, q_, begin, end);
      });
      a.addPairProducts(c_, q_, parallel);
    }
    // q = S A c, alpha = delta / c.q
    const double cq = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      filterChunk(q_, begin, end);
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
  result.relative_residual = std::sqrt(r_norm2 / b_norm2);
  return result;
}

}  // namespace wobble
