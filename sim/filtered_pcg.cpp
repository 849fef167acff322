#include "sim/filtered_pcg.h"

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
                             double tolerance, int max_iterations, bool parallel) {
  const int n = static_cast<int>(b.size() / 3);
  setUpPreconditioner(a, s, parallel);
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

  // r = S (b - A x), c = P^-1 r (filtered), delta = r.c; |r|^2 alongside.
  a.multiply(x, q_, parallel);
  Eigen::Vector2d sums = sumOverChunks(n, parallel, pair_sums_, [&](int begin, int end) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int p = begin; p < end; ++p) {
      const Vec3 r = s.apply(p, particle(b, p) - particle(q_, p));
      const Vec3 c = inverse_[p] * r;
      particle(r_, p) = r;
      particle(c_, p) = c;
      sum += Eigen::Vector2d(r.squaredNorm(), r.dot(c));
    }
    return sum;
  });
  double r_norm2 = sums[0], delta = sums[1], beta = 0;
  PcgResult result;
  // Raw pointers in the loops: through the members, each store would make the compiler reload them.
  double *xs = x.data(), *rs = r_.data(), *cs = c_.data(), *qs = q_.data();
  const Sym3* inverse = inverse_.data();
  const auto at = [](double* v, int p) { return Vec3::Map(v + 3 * p); };
  while (r_norm2 >= threshold && result.iterations < max_iterations) {
    // q = A c, with the direction's update c = z + beta c (z in q) fused into the diagonal part of the product.
    if (result.iterations++ == 0) {
      a.multiply(c_, q_, parallel);
    } else {
      forEachChunk(n, parallel, [&](int begin, int end) {
        for (int p = begin; p < end; ++p) at(cs, p) = at(qs, p) + beta * at(cs, p);
        a.multiplySelf(c_, q_, begin, end);
      });
      a.addPairProducts(c_, q_, parallel);
    }
    // q = S A c, alpha = delta / c.q
    const double cq = sumOverChunks(n, parallel, sums_, [&](int begin, int end) {
      double sum = 0;
      for (int p = begin; p < end; ++p) {
        const Vec3 q = s.apply(p, at(qs, p));
        at(qs, p) = q;
        sum += at(cs, p).dot(q);
      }
      return sum;
    });
    const double alpha = delta / cq;
    // x += alpha c, r -= alpha q; the next preconditioned residual z = P^-1 r and its products.
    sums = sumOverChunks(n, parallel, pair_sums_, [&](int begin, int end) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (int p = begin; p < end; ++p) {
        at(xs, p) += alpha * at(cs, p);
        const Vec3 r = at(rs, p) - alpha * at(qs, p);
        const Vec3 z = inverse[p] * r;
        at(rs, p) = r;
        at(qs, p) = z;  // q is free until the next product: it holds z
        sum += Eigen::Vector2d(r.squaredNorm(), r.dot(z));
      }
      return sum;
    });
    r_norm2 = sums[0];
    beta = sums[1] / delta;
    delta = sums[1];
  }
  result.relative_residual = std::sqrt(r_norm2 / b_norm2);
  return result;
}

}  // namespace wobble
