#include "sim/coarse_correction.h"

#include "sim/aggregation.h"
#include "sim/graph_dissection.h"
#include "sim/parallel.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace wobble {
namespace {

Eigen::Matrix3d filterMatrix(const ParticleFilter& s, int p) {
  switch (s.kind(p)) {
    case ParticleFilter::Free:
      return Eigen::Matrix3d::Identity();
    case ParticleFilter::Held:
      return Eigen::Matrix3d::Zero();
    default:
      return Eigen::Matrix3d::Identity() - s.normal(p) * s.normal(p).transpose();
  }
}

// m += sign b.
void add(Eigen::Matrix3d& m, const Sym3& b, double sign) {
  m(0, 0) += sign * b.xx, m(1, 1) += sign * b.yy, m(2, 2) += sign * b.zz;
  m(0, 1) += sign * b.xy, m(1, 0) += sign * b.xy;
  m(0, 2) += sign * b.xz, m(2, 0) += sign * b.xz;
  m(1, 2) += sign * b.yz, m(2, 1) += sign * b.yz;
}

}  // namespace

void CoarseCorrection::buildPattern(const PairSchedule& pattern) {
  ++pattern_setups_;
  pattern_ = &pattern;
  pattern_pairs_ = pattern.size();
  const int n = pattern.particles();
  aggregate_ = aggregateParticles(pattern.a(), pattern.b(), n, aggregates_);
  // Coarse blocks: one per aggregate, two per pair of neighbouring aggregates.
  std::map<std::pair<int, int>, int> coarse_pairs;
  pair_block_.assign(pattern.size(), -1);
  pair_flipped_.assign(pattern.size(), 0);
  int blocks = aggregates_;
  for (std::size_t e = 0; e < pattern.size(); ++e) {
    const int i = aggregate_[pattern.a()[e]], j = aggregate_[pattern.b()[e]];
    if (i == j) continue;
    const auto [it, added] = coarse_pairs.try_emplace({std::min(i, j), std::max(i, j)}, blocks);
    if (added) blocks += 2;
    pair_block_[e] = it->second;
    pair_flipped_[e] = i > j;
  }
  std::vector<std::pair<int, int>> block_at(blocks);  // (row, column) aggregate of each block
  for (int i = 0; i < aggregates_; ++i) block_at[i] = {i, i};
  for (const auto& [ij, k] : coarse_pairs) block_at[k] = ij, block_at[k + 1] = {ij.second, ij.first};
  // The sparse matrix, its unknowns relabelled once: part 0, part 1, the separator (dissect), each in a fill-reducing
  // (AMD) order of its own. The factorization then needs no permutation of its own, neither it nor the solve
  // allocates, and the factor has no entry between the parts.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(coarse_pairs.size());
  for (const auto& [ij, k] : coarse_pairs) edges.push_back(ij);
  const std::vector<int> part = dissect(aggregates_, edges);
  for (const auto& [i, j] : edges)  // the two parts' solves run at the same time: they must share no entry
    if (part[i] + part[j] == 1) throw std::logic_error("CoarseCorrection: an edge between the dissected parts");
  dof_.assign(3 * aggregates_, -1);
  int next = 0;
  for (int k = 0; k < 3; ++k) {
    part_begin_[k] = next;
    part_aggregates_[k].clear();
    for (int i = 0; i < aggregates_; ++i)
      if (part[i] == k) part_aggregates_[k].push_back(i);
    // AMD on the part with the separator (whose unknowns come after it: their order here is dropped).
    const auto inGraph = [&](int i) { return part[i] == k || part[i] == 2; };
    std::vector<int> local(aggregates_, -1), nodes;
    for (int i = 0; i < aggregates_; ++i)
      if (inGraph(i)) local[i] = int(nodes.size()), nodes.push_back(i);
    const int m = int(nodes.size());
    std::vector<Eigen::Triplet<double>> entries;
    for (const auto& [i, j] : block_at)
      if (inGraph(i) && inGraph(j))
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) entries.emplace_back(3 * local[i] + r, 3 * local[j] + c, 1.0);
    Eigen::SparseMatrix<double> sub(3 * m, 3 * m);
    sub.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> fill_order;
    Eigen::AMDOrdering<int>()(sub.selfadjointView<Eigen::Upper>(), fill_order);
    for (int position = 0; position < 3 * m; ++position) {
      const int d = fill_order.indices()[position];
      if (part[nodes[d / 3]] == k) dof_[3 * nodes[d / 3] + d % 3] = next++;
    }
  }
  part_begin_[3] = next;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * blocks);
  for (const auto& [i, j] : block_at)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) entries.emplace_back(dof_[3 * i + r], dof_[3 * j + c], 1.0);
  matrix_.resize(3 * aggregates_, 3 * aggregates_);
  matrix_.setFromTriplets(entries.begin(), entries.end());
  matrix_.makeCompressed();
  block_entry_.resize(9 * blocks);
  for (int k = 0; k < blocks; ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const int row = dof_[3 * block_at[k].first + r], col = dof_[3 * block_at[k].second + c];
        const int* rows = matrix_.innerIndexPtr();
        const int* first = rows + matrix_.outerIndexPtr()[col];
        const int* last = rows + matrix_.outerIndexPtr()[col + 1];
        block_entry_[9 * k + 3 * r + c] = int(std::lower_bound(first, last, row) - rows);
      }
  blocks_.assign(blocks, Eigen::Matrix3d::Zero());
  gram_.assign(aggregates_, Eigen::Matrix3d::Zero());
  size_.assign(aggregates_, 0);
  for (int p = 0; p < n; ++p) ++size_[aggregate_[p]];
  member_start_.assign(aggregates_ + 1, 0);
  for (int i = 0; i < aggregates_; ++i) member_start_[i + 1] = member_start_[i] + size_[i];
  members_.resize(n);
  std::vector<int> filled(member_start_.begin(), member_start_.end() - 1);
  for (int p = 0; p < n; ++p) members_[filled[aggregate_[p]]++] = p;
  ldlt_.analyzePattern(matrix_);
  y_.setZero(3 * aggregates_);
  u_.setZero(3 * aggregates_);
  const int separator = part_begin_[3] - part_begin_[2];
  separator_terms_[0].setZero(separator);
  separator_terms_[1].setZero(separator);
}

bool CoarseCorrection::fits(const PairBlockMatrix& a) const {
  const PairSchedule& pattern = *a.pattern();
  return pattern_ == &pattern && pattern_pairs_ == pattern.size() && int(aggregate_.size()) == pattern.particles();
}

void CoarseCorrection::setUp(const PairBlockMatrix& a, const ParticleFilter& s) {
  const PairSchedule& pattern = *a.pattern();
  if (!fits(a)) buildPattern(pattern);
  ++factorizations_;
  for (Eigen::Matrix3d& b : blocks_) b.setZero();
  const int n = pattern.particles();
  const auto filtered = [&](int p) { return s.kind(p) != ParticleFilter::Free; };
  // Z^T S A S Z: each particle's self block, each pair's four blocks, filtered on both sides.
  for (int p = 0; p < n; ++p) {
    if (!filtered(p)) {
      add(blocks_[aggregate_[p]], Sym3::identity(a.self()[p]), 1);
    } else if (s.kind(p) != ParticleFilter::Held) {
      const Eigen::Matrix3d sp = filterMatrix(s, p);
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
    const Eigen::Matrix3d sa = filterMatrix(s, pa_e), sb = filterMatrix(s, pb_e);
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
  // An aggregate whose particles are all held, or all constrained along one normal, has coarse directions that S
  // removes (Z^T S Z, the Gram matrix of its three columns, is singular there; so are its rows and columns of the
  // matrix): the identity there keeps the matrix invertible and leaves those directions at 0.
  for (int i = 0; i < aggregates_; ++i) gram_[i] = Eigen::Matrix3d::Identity() * size_[i];
  bool any = false;
  for (int p = 0; p < n; ++p)
    if (filtered(p)) gram_[aggregate_[p]] += filterMatrix(s, p) - Eigen::Matrix3d::Identity(), any = true;
  for (int i = 0; any && i < aggregates_; ++i) {
    if (gram_[i].trace() > 3 * size_[i] - 0.5) continue;  // every particle free
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(gram_[i]);
    for (int k = 0; k < 3; ++k)
      if (eigen.eigenvalues()[k] < 1e-9) {
        const Vec3 v = eigen.eigenvectors().col(k);
        blocks_[i] += v * v.transpose();
      }
  }
  double* values = matrix_.valuePtr();
  for (std::size_t k = 0; k < blocks_.size(); ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) values[block_entry_[9 * k + 3 * r + c]] = blocks_[k](r, c);
  ldlt_.factorize(matrix_);
}

template <class T>
void CoarseCorrection::restrictAndSolveForward(const T* r, int k) {
  for (int i : part_aggregates_[k]) {
    double sum[3] = {0, 0, 0};
    for (int m = member_start_[i]; m < member_start_[i + 1]; ++m)
      for (int c = 0; c < 3; ++c) sum[c] += r[3 * members_[m] + c];
    for (int c = 0; c < 3; ++c) y_[dof_[3 * i + c]] = sum[c];
  }
  if (k == 2) return;
  // L y = b over the part's columns (L unit lower, stored without its diagonal, column by column as Eigen's
  // SimplicialLDLT keeps it): rows in the part are updated in place, those in the separator summed aside.
  const auto& l = ldlt_.matrixL().nestedExpression();
  const int* outer = l.outerIndexPtr();
  const int* rows = l.innerIndexPtr();
  const double* values = l.valuePtr();
  const int separator = part_begin_[2];
  double* terms = separator_terms_[k].data();
  std::fill(terms, terms + separator_terms_[k].size(), 0.0);
  for (int j = part_begin_[k]; j < part_begin_[k + 1]; ++j) {
    const double yj = y_[j];
    for (int e = outer[j]; e < outer[j + 1]; ++e) {
      if (rows[e] < separator) y_[rows[e]] -= values[e] * yj;
      else terms[rows[e] - separator] += values[e] * yj;
    }
  }
}

void CoarseCorrection::solveBackward(int k) {
  // L^T x = y over part k's columns, last to first: each column reads rows below it (its part and the separator).
  const auto& l = ldlt_.matrixL().nestedExpression();
  const int* outer = l.outerIndexPtr();
  const int* rows = l.innerIndexPtr();
  const double* values = l.valuePtr();
  // Each column's dot product in four running sums: one sum is a chain of dependent additions (an addition's latency
  // an entry), four keep the loads busy instead. The same order whatever the thread count.
  for (int j = part_begin_[k + 1] - 1; j >= part_begin_[k]; --j) {
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int e = outer[j];
    const int end = outer[j + 1];
    for (; e + 4 <= end; e += 4) {
      s0 += values[e] * y_[rows[e]];
      s1 += values[e + 1] * y_[rows[e + 1]];
      s2 += values[e + 2] * y_[rows[e + 2]];
      s3 += values[e + 3] * y_[rows[e + 3]];
    }
    for (; e < end; ++e) s0 += values[e] * y_[rows[e]];
    y_[j] -= (s0 + s1) + (s2 + s3);
  }
}

void CoarseCorrection::solve(const double* r, bool parallel) { solveFor(r, parallel); }
void CoarseCorrection::solve(const float* r, bool parallel) { solveFor(r, parallel); }

template <class T>
void CoarseCorrection::solveFor(const T* r, bool parallel) {
  if (ldlt_.info() != Eigen::Success) {  // not positive definite (it is by construction): no correction
    u_.setZero();
    return;
  }
  // The two parts' restriction and forward solve, at the same time when parallel; then the separator's.
  runBoth(
      parallel, [&] { restrictAndSolveForward(r, 0); }, [&] { restrictAndSolveForward(r, 1); });
  restrictAndSolveForward(r, 2);
  const int separator = part_begin_[2];
  for (int j = separator; j < part_begin_[3]; ++j)
    y_[j] = y_[j] - separator_terms_[0][j - separator] - separator_terms_[1][j - separator];
  const auto& l = ldlt_.matrixL().nestedExpression();
  const int* outer = l.outerIndexPtr();
  const int* rows = l.innerIndexPtr();
  const double* values = l.valuePtr();
  for (int j = separator; j < part_begin_[3]; ++j)  // the separator's forward solve: its rows only
    for (int e = outer[j]; e < outer[j + 1]; ++e) y_[rows[e]] -= values[e] * y_[j];
  const auto& d = ldlt_.vectorD();
  for (int j = 0; j < part_begin_[3]; ++j) y_[j] /= d[j];
  solveBackward(2);
  runBoth(
      parallel, [&] { solveBackward(0); }, [&] { solveBackward(1); });
  for (int c = 0; c < 3 * aggregates_; ++c) u_[c] = y_[dof_[c]];
}

}  // namespace wobble
