// A sparse LDL^T factorization of a symmetric positive definite matrix of 3 x 3 blocks (the coarse level's Galerkin
// matrix, coarse_correction.h): A = L D L^T, L unit lower-triangular by blocks, D block-diagonal with full 3 x 3
// blocks. It works on blocks where a scalar factorization (Eigen's SimplicialLDLT) walks one index per number: a
// block's update is a fixed-size 3 x 3 product, nine times fewer index lookups and independent multiplications to
// overlap, on the factorization and on the triangular solves alike (measured: docs/performance.md).
// The block order is the caller's: a fill-reducing order within one level of nested dissection, block columns
// [0, p1) (part 0), [p1, p2) (part 1) and [p2, n) (the separator), with no block between parts 0 and 1. Their
// columns then never meet: the factorization computes each column from the columns to its left (left-looking), so
// the two parts' columns are computed at the same time when parallel, then the separator's; the solves run the two
// parts as two tasks too. Every sum is taken in one fixed order, so the bytes do not depend on the thread count.
#pragma once
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sim/solver/parallel.h"

namespace wobble {

class BlockLdlt {
 public:
  using Block = Eigen::Matrix3d;

  // The pattern: n block columns, A's blocks below the diagonal as (row, column) with row > column, no repeats; the
  // parts' first columns p1 <= p2. Throws std::invalid_argument for a block between parts 0 and 1.
  void analyze(int n, const std::vector<std::pair<int, int>>& lower, int p1, int p2);
  // A's values, filled by the caller before factorize(): the diagonal blocks, and the lower blocks in analyze's order.
  Block& diagonal(int j) { return a_diagonal_[j]; }
  Block& lower(int k) { return a_lower_[k]; }
  // L and D from A's values; false (and solve() gives 0) when a pivot block is not positive definite.
  bool factorize(bool parallel);
  bool ok() const { return ok_; }

  // y = A^-1 y (3 values per block column, in the factorization's order). fill(k), for k = 0, 1, 2, writes part k's
  // values of y (the right-hand side) just before its forward solve, on the part's task: callers restrict into y there.
  template <class Fill>
  void solve(double* y, bool parallel, Fill&& fill);
  void solve(double* y, bool parallel = false) {
    solve(y, parallel, [](int) {});
  }

  int size() const { return n_; }
  std::size_t factorBlocks() const { return rows_.size(); }  // L's blocks below the diagonal

 private:
  // Part k's columns (k = 0, 1) or the separator's (k = 2); work: a block per row, scratch of the task.
  bool factorizeColumns(int k, std::vector<Block>& work);  // false at a pivot that is not positive definite
  // Forward solve of part k's columns (L y = b, then D^-1), their terms in separator rows summed into terms_[k].
  void forward(int k, double* y);
  void forwardSeparator(double* y);
  void backward(int k, double* y);  // L^T x = y over part k's columns, last to first

  int n_ = 0;
  int begin_[4] = {};  // columns of part 0, part 1, the separator: [begin_[k], begin_[k + 1])
  std::vector<Block> a_diagonal_, a_lower_;
  std::vector<std::vector<std::pair<int, int>>> a_column_;  // per column: A's lower blocks (row, index in a_lower_)
  // L by columns: rows (ascending) and blocks of column j in [start_[j], start_[j + 1]).
  std::vector<int> start_, rows_;
  std::vector<Block> l_;
  // Per column j: the entries (k, e) of row j left of the diagonal, L_jk = l_[e], k ascending.
  std::vector<int> row_start_;
  std::vector<std::pair<int, int>> row_entries_;
  std::vector<Block> d_, d_inverse_;
  std::vector<Block> work_[2];
  std::vector<double> terms_[2];  // per part: its forward terms in the separator's rows
  bool ok_ = false;
};

template <class Fill>
void BlockLdlt::solve(double* y, bool parallel, Fill&& fill) {
  if (!ok_) {
    std::fill(y, y + 3 * n_, 0.0);
    return;
  }
  const auto part = [&](int k) {
    fill(k);
    forward(k, y);
  };
  runBoth(
      parallel, [&] { part(0); }, [&] { part(1); });
  fill(2);
  forwardSeparator(y);
  backward(2, y);
  runBoth(
      parallel, [&] { backward(0, y); }, [&] { backward(1, y); });
}

}  // namespace wobble
