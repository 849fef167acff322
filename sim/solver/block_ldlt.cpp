#include "sim/solver/block_ldlt.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>

namespace wobble {

using Vec3d = Eigen::Vector3d;

void BlockLdlt::analyze(int n, const std::vector<std::pair<int, int>>& lower, int p1, int p2) {
  if (!(0 <= p1 && p1 <= p2 && p2 <= n)) throw std::invalid_argument("BlockLdlt: parts out of order");
  n_ = n;
  begin_[0] = 0, begin_[1] = p1, begin_[2] = p2, begin_[3] = n;
  const auto partOf = [&](int j) { return j < p1 ? 0 : j < p2 ? 1 : 2; };
  a_diagonal_.assign(n, Block::Zero());
  a_lower_.assign(lower.size(), Block::Zero());
  a_column_.assign(n, {});
  for (std::size_t k = 0; k < lower.size(); ++k) {
    const auto [i, j] = lower[k];
    if (!(0 <= j && j < i && i < n)) throw std::invalid_argument("BlockLdlt: a lower block off the lower triangle");
    if (partOf(i) + partOf(j) == 1) throw std::invalid_argument("BlockLdlt: a block between parts 0 and 1");
    a_column_[j].emplace_back(i, int(k));
  }
  // Symbolic factorization: column j's rows are A's below the diagonal and those below j of its children in the
  // elimination tree (the columns whose first row is j). Part 0's columns thus reach part 0 and the separator only.
  std::vector<std::vector<int>> children(n);
  std::vector<int> mark(n, -1), pattern;
  start_.assign(1, 0);
  rows_.clear();
  for (int j = 0; j < n; ++j) {
    std::sort(a_column_[j].begin(), a_column_[j].end());
    pattern.clear();
    for (const auto& [i, k] : a_column_[j])
      if (mark[i] != j) mark[i] = j, pattern.push_back(i);
    for (int c : children[j])
      for (int e = start_[c]; e < start_[c + 1]; ++e)
        if (rows_[e] > j && mark[rows_[e]] != j) mark[rows_[e]] = j, pattern.push_back(rows_[e]);
    std::sort(pattern.begin(), pattern.end());
    rows_.insert(rows_.end(), pattern.begin(), pattern.end());
    start_.push_back(int(rows_.size()));
    if (!pattern.empty()) children[pattern[0]].push_back(j);
  }
  l_.assign(rows_.size(), Block::Zero());
  // The rows' entries, each row's in ascending column order.
  row_start_.assign(n + 1, 0);
  for (int i : rows_) ++row_start_[i + 1];
  for (int j = 0; j < n; ++j) row_start_[j + 1] += row_start_[j];
  row_entries_.resize(rows_.size());
  std::vector<int> next(row_start_.begin(), row_start_.end() - 1);
  for (int k = 0; k < n; ++k)
    for (int e = start_[k]; e < start_[k + 1]; ++e) row_entries_[next[rows_[e]]++] = {k, e};
  d_.assign(n, Block::Zero());
  d_inverse_.assign(n, Block::Zero());
  for (std::vector<Block>& w : work_) w.assign(n, Block::Zero());
  for (std::vector<double>& t : terms_) t.assign(3 * (n - p2), 0.0);
  ok_ = false;
}

bool BlockLdlt::factorize(bool parallel) {
  bool ok[3] = {true, true, true};
  runBoth(
      parallel, [&] { ok[0] = factorizeColumns(0, work_[0]); }, [&] { ok[1] = factorizeColumns(1, work_[1]); });
  ok[2] = ok[0] && ok[1] && factorizeColumns(2, work_[0]);
  ok_ = ok[0] && ok[1] && ok[2];
  return ok_;
}

bool BlockLdlt::factorizeColumns(int k, std::vector<Block>& work) {
  for (int j = begin_[k]; j < begin_[k + 1]; ++j) {
    // work = column j of A - sum over k of L_.k D_k L_jk^T (the columns k left of j with L_jk != 0, in order).
    work[j] = a_diagonal_[j];
    for (int e = start_[j]; e < start_[j + 1]; ++e) work[rows_[e]].setZero();
    for (const auto& [i, index] : a_column_[j]) work[i] = a_lower_[index];
    for (int r = row_start_[j]; r < row_start_[j + 1]; ++r) {
      const auto [column, e] = row_entries_[r];
      const Block m = d_[column] * l_[e].transpose();  // D_k L_jk^T
      work[j].noalias() -= l_[e] * m;
      for (int f = e + 1; f < start_[column + 1]; ++f) work[rows_[f]].noalias() -= l_[f] * m;
    }
    d_[j] = 0.5 * (work[j] + work[j].transpose());
    const Eigen::LLT<Block> llt(d_[j]);
    if (llt.info() != Eigen::Success) return false;
    d_inverse_[j] = llt.solve(Block::Identity());
    for (int e = start_[j]; e < start_[j + 1]; ++e) l_[e].noalias() = work[rows_[e]] * d_inverse_[j];
  }
  return true;
}

void BlockLdlt::forward(int k, double* y) {
  const int separator = begin_[2];
  double* terms = terms_[k].data();
  std::fill(terms_[k].begin(), terms_[k].end(), 0.0);
  for (int j = begin_[k]; j < begin_[k + 1]; ++j) {
    const Vec3d yj = Vec3d::Map(y + 3 * j);
    for (int e = start_[j]; e < start_[j + 1]; ++e) {
      const int i = rows_[e];
      if (i < separator) Vec3d::Map(y + 3 * i).noalias() -= l_[e] * yj;
      else Vec3d::Map(terms + 3 * (i - separator)).noalias() += l_[e] * yj;
    }
  }
  for (int j = begin_[k]; j < begin_[k + 1]; ++j) Vec3d::Map(y + 3 * j) = d_inverse_[j] * Vec3d::Map(y + 3 * j);
}

void BlockLdlt::forwardSeparator(double* y) {
  const int separator = begin_[2];
  for (int c = 0; c < 3 * (n_ - separator); ++c)
    y[3 * separator + c] = y[3 * separator + c] - terms_[0][c] - terms_[1][c];
  for (int j = separator; j < n_; ++j) {
    const Vec3d yj = Vec3d::Map(y + 3 * j);
    for (int e = start_[j]; e < start_[j + 1]; ++e) Vec3d::Map(y + 3 * rows_[e]).noalias() -= l_[e] * yj;
  }
  for (int j = separator; j < n_; ++j) Vec3d::Map(y + 3 * j) = d_inverse_[j] * Vec3d::Map(y + 3 * j);
}

void BlockLdlt::backward(int k, double* y) {
  for (int j = begin_[k + 1] - 1; j >= begin_[k]; --j) {
    Vec3d sum = Vec3d::Zero();
    for (int e = start_[j]; e < start_[j + 1]; ++e) sum.noalias() += l_[e].transpose() * Vec3d::Map(y + 3 * rows_[e]);
    Vec3d::Map(y + 3 * j) -= sum;
  }
}

}  // namespace wobble
