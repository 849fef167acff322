#include "sim/solver/coarse_correction.h"

#include "sim/solver/aggregation.h"
#include "sim/solver/graph_dissection.h"
#include "sim/solver/parallel.h"

#include <Eigen/Eigenvalues>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace wobble {
namespace {

// m += sign b.
void add(Eigen::Matrix3d& m, const Sym3& b, double sign) {
  m(0, 0) += sign * b.xx, m(1, 1) += sign * b.yy, m(2, 2) += sign * b.zz;
  m(0, 1) += sign * b.xy, m(1, 0) += sign * b.xy;
  m(0, 2) += sign * b.xz, m(2, 0) += sign * b.xz;
  m(1, 2) += sign * b.yz, m(2, 1) += sign * b.yz;
}

// A stencil's particles grouped by aggregate (each aggregate once, in the order of its first particle): per
// aggregate I its M_I = sum over the stencil's particles p_i in I of w_i S_(p_i), as W_I I + the filtered particles'
// w_i (S_(p_i) - I) (filter given). Weights of 0 are left out.
struct StencilAggregates {
  int size = 0;
  int aggregate[WeightedStencil::kCapacity];
  double weight[WeightedStencil::kCapacity];
  Eigen::Matrix3d filtered_part[WeightedStencil::kCapacity];

  StencilAggregates(const WeightedStencil& st, const int* aggregates, const ParticleFilter* s = nullptr) {
    for (int i = 0; i < st.size; ++i) {
      if (st.w[i] == 0) continue;
      const int p = st.particle[i], agg = aggregates[p];
      int x = 0;
      while (x < size && aggregate[x] != agg) ++x;
      if (x == size) {
        aggregate[size] = agg, weight[size] = 0;
        if (s) filtered_part[size].setZero();
        ++size;
      }
      weight[x] += st.w[i];
      if (s && s->kind(p) != ParticleFilter::Free)
        filtered_part[x] += st.w[i] * (s->matrix(p) - Eigen::Matrix3d::Identity());
    }
  }
};

}  // namespace

void CoarseCorrection::buildAggregates(const PairSchedule& pattern) {
  ++pattern_setups_;
  pattern_ = &pattern;
  pattern_pairs_ = pattern.size();
  const int n = pattern.particles();
  aggregate_ = aggregateParticles(pattern.a(), pattern.b(), n, aggregates_);
  // Coarse blocks: one per aggregate, two per pair of neighbouring aggregates.
  coarse_pairs_.clear();
  pair_block_.assign(pattern.size(), -1);
  pair_flipped_.assign(pattern.size(), 0);
  int blocks = aggregates_;
  for (std::size_t e = 0; e < pattern.size(); ++e) {
    const int i = aggregate_[pattern.a()[e]], j = aggregate_[pattern.b()[e]];
    if (i == j) continue;
    const auto [it, added] = coarse_pairs_.try_emplace({std::min(i, j), std::max(i, j)}, blocks);
    if (added) blocks += 2;
    pair_block_[e] = it->second;
    pair_flipped_[e] = i > j;
  }
  spring_blocks_ = blocks;
  stencil_pairs_ = 0;
  gram_.assign(aggregates_, Eigen::Matrix3d::Zero());
  size_.assign(aggregates_, 0);
  for (int p = 0; p < n; ++p) ++size_[aggregate_[p]];
  member_start_.assign(aggregates_ + 1, 0);
  for (int i = 0; i < aggregates_; ++i) member_start_[i + 1] = member_start_[i] + size_[i];
  members_.resize(n);
  std::vector<int> filled(member_start_.begin(), member_start_.end() - 1);
  for (int p = 0; p < n; ++p) members_[filled[aggregate_[p]]++] = p;
  y_.setZero(3 * aggregates_);
  u_.setZero(3 * aggregates_);
}

void CoarseCorrection::buildCoarsePattern() {
  ++coarse_patterns_;
  // The coarse matrix's block columns, aggregates relabelled once: part 0, part 1, the separator (dissect), each in a
  // fill-reducing (AMD) order of its own. The factorization then needs no permutation, and the factor has no block
  // between the parts.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(coarse_pairs_.size());
  for (const auto& [ij, k] : coarse_pairs_) edges.push_back(ij);
  const std::vector<int> part = dissect(aggregates_, edges);
  for (const auto& [i, j] : edges)  // the two parts' solves run at the same time: they must share no entry
    if (part[i] + part[j] == 1) throw std::logic_error("CoarseCorrection: an edge between the dissected parts");
  column_.assign(aggregates_, -1);
  int next = 0, part_begin[3] = {};
  for (int k = 0; k < 3; ++k) {
    part_begin[k] = next;
    part_aggregates_[k].clear();
    for (int i = 0; i < aggregates_; ++i)
      if (part[i] == k) part_aggregates_[k].push_back(i);
    // AMD on the part with the separator (whose columns come after it: their order here is dropped).
    const auto inGraph = [&](int i) { return part[i] == k || part[i] == 2; };
    std::vector<int> local(aggregates_, -1), nodes;
    for (int i = 0; i < aggregates_; ++i)
      if (inGraph(i)) local[i] = int(nodes.size()), nodes.push_back(i);
    std::vector<Eigen::Triplet<double>> entries;
    for (int i : nodes) entries.emplace_back(local[i], local[i], 1.0);
    for (const auto& [i, j] : edges)
      if (inGraph(i) && inGraph(j))
        entries.emplace_back(local[i], local[j], 1.0), entries.emplace_back(local[j], local[i], 1.0);
    Eigen::SparseMatrix<double> graph(int(nodes.size()), int(nodes.size()));
    graph.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> fill_order;
    Eigen::AMDOrdering<int>()(graph.selfadjointView<Eigen::Upper>(), fill_order);
    for (int position = 0; position < int(nodes.size()); ++position) {
      const int i = nodes[fill_order.indices()[position]];
      if (part[i] == k) column_[i] = next++;
    }
  }
  // The factor's lower blocks: per pair of neighbouring aggregates, block (I, J) or (J, I), whichever is below the
  // diagonal; and per aggregate its neighbours of higher number with their blocks (pairBlock).
  std::vector<std::pair<int, int>> lower;
  lower_block_.clear();
  neighbour_start_.assign(aggregates_ + 1, 0);
  neighbours_.clear();
  for (const auto& [ij, k] : coarse_pairs_) {
    const auto [i, j] = ij;
    const bool i_below = column_[i] > column_[j];
    lower.emplace_back(i_below ? column_[i] : column_[j], i_below ? column_[j] : column_[i]);
    lower_block_.push_back(i_below ? k : k + 1);  // block (I, J) is row I's
    ++neighbour_start_[i + 1];
    neighbours_.emplace_back(j, k);  // the map's order: by i, then j
  }
  for (int i = 0; i < aggregates_; ++i) neighbour_start_[i + 1] += neighbour_start_[i];
  ldlt_.analyze(aggregates_, lower, part_begin[1], part_begin[2]);
  blocks_.assign(aggregates_ + 2 * coarse_pairs_.size(), Eigen::Matrix3d::Zero());
}

int CoarseCorrection::pairBlock(int i, int j) const {
  const auto first = neighbours_.begin() + neighbour_start_[i], last = neighbours_.begin() + neighbour_start_[i + 1];
  const auto it = std::lower_bound(first, last, std::pair<int, int>{j, -1});
  return it != last && it->first == j ? it->second : -1;
}

bool CoarseCorrection::fits(const PairBlockMatrix& a) const {
  const PairSchedule& pattern = *a.pattern();
  return pattern_ == &pattern && pattern_pairs_ == pattern.size() && int(aggregate_.size()) == pattern.particles();
}

void CoarseCorrection::setUp(const PairBlockMatrix& a, const ParticleFilter& s, bool parallel) {
  const PairSchedule& pattern = *a.pattern();
  if (!fits(a)) buildAggregates(pattern), buildCoarsePattern();
  // The stencils' pairs of aggregates: the pattern extended when it lacks any (the pairs added are kept while the
  // topology stands, so that contact that comes and goes over the same places does not rebuild it every time).
  // But when those the stencils at hand do not use outnumber those they do (the contact has moved on), a rebuild keeps
  // only these: a cloth sliding over itself for long would otherwise fill the coarse factor.
  if (coverStencils(a.stencils())) {
    if (stencil_pairs_ > 2 * used_stencil_pairs_) {
      for (auto it = coarse_pairs_.begin(); it != coarse_pairs_.end();)
        it = it->second >= spring_blocks_ ? coarse_pairs_.erase(it) : std::next(it);
      stencil_pairs_ = 0;
      coverStencils(a.stencils());
    }
    buildCoarsePattern();
  }
  ++factorizations_;
  for (Eigen::Matrix3d& b : blocks_) b.setZero();
  const int n = pattern.particles();
  const auto filtered = [&](int p) { return s.kind(p) != ParticleFilter::Free; };
  // Z^T S A S Z: each particle's self block, each pair's four blocks, filtered on both sides.
  for (int p = 0; p < n; ++p) {
    if (!filtered(p)) {
      add(blocks_[aggregate_[p]], Sym3::identity(a.self()[p]), 1);
    } else if (s.kind(p) != ParticleFilter::Held) {
      const Eigen::Matrix3d sp = s.matrix(p);
      blocks_[aggregate_[p]] += a.self()[p] * (sp * sp);
    }
  }
  const int* pa = pattern.a().data();
  const int* pb = pattern.b().data();
  for (std::size_t e = 0; e < pattern.size(); ++e) {
    const int pa_e = pa[e], pb_e = pb[e];
    const int block = pair_block_[e];
    if (!filtered(pa_e) && !filtered(pb_e)) {
      if (block < 0) continue;  // a free pair inside an aggregate: the aggregate's translation does not strain it
      const Sym3 w = a.pair(e);
      add(blocks_[aggregate_[pa_e]], w, 1);
      add(blocks_[aggregate_[pb_e]], w, 1);
      add(blocks_[block], w, -1);
      add(blocks_[block + 1], w, -1);
      continue;
    }
    const Eigen::Matrix3d w = a.pair(e).dense();
    const Eigen::Matrix3d sa = s.matrix(pa_e), sb = s.matrix(pb_e);
    const Eigen::Matrix3d ab = sa * w * sb;
    if (block < 0) {
      blocks_[aggregate_[pa_e]] += sa * w * sa + sb * w * sb - ab - ab.transpose();
      continue;
    }
    blocks_[aggregate_[pa_e]] += sa * w * sa;
    blocks_[aggregate_[pb_e]] += sb * w * sb;
    // Block (I, J) with I < J: (a, b)'s block when a is in I, else (b, a)'s.
    blocks_[block] -= pair_flipped_[e] ? Eigen::Matrix3d(ab.transpose()) : ab;
    blocks_[block + 1] -= pair_flipped_[e] ? ab : Eigen::Matrix3d(ab.transpose());
  }
  addStencils(a.stencils(), s);
  // An aggregate whose particles are all held, or all constrained along one normal or one line, has coarse directions
  // that S removes (Z^T S Z, the Gram matrix of its three columns, is singular there; so are its rows and columns of
  // the matrix): the identity there keeps the matrix invertible and leaves those directions at 0.
  for (int i = 0; i < aggregates_; ++i) gram_[i] = Eigen::Matrix3d::Identity() * size_[i];
  bool any = false;
  for (int p = 0; p < n; ++p)
    if (filtered(p)) gram_[aggregate_[p]] += s.matrix(p) - Eigen::Matrix3d::Identity(), any = true;
  for (int i = 0; any && i < aggregates_; ++i) {
    if (gram_[i].trace() > 3 * size_[i] - 0.5) continue;  // every particle free
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(gram_[i]);
    for (int k = 0; k < 3; ++k)
      if (eigen.eigenvalues()[k] < 1e-9) {
        const Vec3 v = eigen.eigenvectors().col(k);
        blocks_[i] += v * v.transpose();
      }
  }
  for (int i = 0; i < aggregates_; ++i) ldlt_.diagonal(column_[i]) = blocks_[i];
  for (std::size_t k = 0; k < lower_block_.size(); ++k) ldlt_.lower(int(k)) = blocks_[lower_block_[k]];
  ldlt_.factorize(parallel);
}

bool CoarseCorrection::coverStencils(const StencilCouplings& stencils) {
  bool added = false;
  used_stencil_pairs_ = 0;
  stencil_pair_used_.assign(stencil_pairs_, 0);
  group_start_.assign(1, 0);
  group_aggregate_.clear();
  group_weight_.clear();
  group_pair_block_.clear();
  for (const StencilBlock& sb : stencils) {
    const StencilAggregates g(sb.stencil, aggregate_.data());
    for (int x = 0; x < g.size; ++x) {
      group_aggregate_.push_back(g.aggregate[x]);
      group_weight_.push_back(g.weight[x]);
      for (int y = x + 1; y < g.size; ++y) {
        const int i = std::min(g.aggregate[x], g.aggregate[y]), j = std::max(g.aggregate[x], g.aggregate[y]);
        int block = pairBlock(i, j);
        if (block < 0) {
          // Not in the factor's pattern: a new pair of blocks, numbered after the others (which keep theirs), or one
          // an earlier stencil added.
          const auto [it, is_new] = coarse_pairs_.try_emplace({i, j}, aggregates_ + 2 * int(coarse_pairs_.size()));
          if (is_new) ++stencil_pairs_, stencil_pair_used_.push_back(0), added = true;
          block = it->second;
        }
        if (block >= spring_blocks_ && !stencil_pair_used_[(block - spring_blocks_) / 2])
          stencil_pair_used_[(block - spring_blocks_) / 2] = 1, ++used_stencil_pairs_;
        group_pair_block_.push_back(block);
      }
    }
    group_start_.push_back(int(group_aggregate_.size()));
  }
  return added;
}

void CoarseCorrection::addStencils(const StencilCouplings& stencils, const ParticleFilter& s) {
  const int* pair_block = group_pair_block_.data();
  int k = 0;
  for (const StencilBlock& sb : stencils) {
    const int first = group_start_[k], size = group_start_[k + 1] - first;
    const int* aggregate = group_aggregate_.data() + first;
    const double* weight = group_weight_.data() + first;
    ++k;
    bool filtered = false;
    for (int i = 0; i < sb.stencil.size && !filtered; ++i)
      filtered = sb.stencil.w[i] != 0 && s.kind(sb.stencil.particle[i]) != ParticleFilter::Free;
    if (!filtered) {  // M_I = W_I I: W_I W_J B
      for (int x = 0; x < size; ++x) {
        add(blocks_[aggregate[x]], sb.block, weight[x] * weight[x]);
        for (int y = x + 1; y < size; ++y, ++pair_block) {
          add(blocks_[*pair_block], sb.block, weight[x] * weight[y]);
          add(blocks_[*pair_block + 1], sb.block, weight[x] * weight[y]);
        }
      }
      continue;
    }
    const StencilAggregates g(sb.stencil, aggregate_.data(), &s);  // the same groups, in the same order
    const Eigen::Matrix3d b = sb.block.dense();
    Eigen::Matrix3d m[WeightedStencil::kCapacity];
    for (int x = 0; x < size; ++x) m[x] = g.weight[x] * Eigen::Matrix3d::Identity() + g.filtered_part[x];
    for (int x = 0; x < size; ++x) {
      blocks_[aggregate[x]] += m[x] * b * m[x];
      for (int y = x + 1; y < size; ++y, ++pair_block) {
        const Eigen::Matrix3d xy = m[x] * b * m[y];  // block (I, J) for I = x's aggregate, J = y's
        const bool ordered = aggregate[x] < aggregate[y];
        blocks_[*pair_block] += ordered ? xy : Eigen::Matrix3d(xy.transpose());
        blocks_[*pair_block + 1] += ordered ? Eigen::Matrix3d(xy.transpose()) : xy;
      }
    }
  }
}

template <class T>
void CoarseCorrection::restrict(const T* r, int k) {
  for (int i : part_aggregates_[k]) {
    double sum[3] = {0, 0, 0};
    for (int m = member_start_[i]; m < member_start_[i + 1]; ++m)
      for (int c = 0; c < 3; ++c) sum[c] += r[3 * members_[m] + c];
    for (int c = 0; c < 3; ++c) y_[3 * column_[i] + c] = sum[c];
  }
}

void CoarseCorrection::solve(const double* r, bool parallel) { solveFor(r, parallel); }
void CoarseCorrection::solve(const float* r, bool parallel) { solveFor(r, parallel); }

template <class T>
void CoarseCorrection::solveFor(const T* r, bool parallel) {
  // Each part's restriction on the task of its forward solve.
  ldlt_.solve(y_.data(), parallel, [&](int k) { restrict(r, k); });
  for (int i = 0; i < aggregates_; ++i)
    for (int c = 0; c < 3; ++c) u_[3 * i + c] = y_[3 * column_[i] + c];
}

}  // namespace wobble
