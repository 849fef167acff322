#include "pair_block_matrix.h"

namespace wobble {

void PairBlockMatrix::reset(const PairSchedule& pattern) {
  pattern_ = &pattern;
  self_.assign(pattern.particles(), Sym3{});
  pair_.assign(pattern.size(), Sym3{});
}

void PairBlockMatrix::diagonal(std::vector<Sym3>& out, bool parallel) const {
  out = self_;
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  pattern_->run(parallel, [&](int begin, int end) {
    for (int e = begin; e < end; ++e) {
      out[a[e]] += pair_[e];
      out[b[e]] += pair_[e];
    }
  });
}

void PairBlockMatrix::multiplySelf(const VecX& x, VecX& y, int begin, int end) const {
  for (int p = begin; p < end; ++p) particle(y, p) = self_[p] * particle(x, p);
}

void PairBlockMatrix::addPairProducts(const VecX& x, VecX& y, bool parallel) const {
  const int* a = pattern_->a().data();
  const int* b = pattern_->b().data();
  pattern_->run(parallel, [&](int begin, int end) {
    for (int e = begin; e < end; ++e) {
      const Vec3 u = pair_[e] * (particle(x, a[e]) - particle(x, b[e]));
      particle(y, a[e]) += u;
      particle(y, b[e]) -= u;
    }
  });
}

void PairBlockMatrix::multiply(const VecX& x, VecX& y, bool parallel) const {
  y.resize(x.size());
  forEachChunk(pattern_->particles(), parallel, [&](int begin, int end) { multiplySelf(x, y, begin, end); });
  addPairProducts(x, y, parallel);
}

}  // namespace wobble
