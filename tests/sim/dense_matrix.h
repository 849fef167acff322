// A PairBlockMatrix written out as a dense matrix, block by block (tests' oracle for its products): the self blocks,
// each pattern pair's W_e on (a, a) and (b, b) and -W_e on (a, b) and (b, a), and each stencil's w_i w_j B.
#pragma once
#include <Eigen/Dense>

#include "sim/solver/pair_block_matrix.h"

namespace wobble::testing {

inline Eigen::MatrixXd denseMatrix(const PairBlockMatrix& a) {
  const int n = int(a.self().size());
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int p = 0; p < n; ++p) dense.block<3, 3>(3 * p, 3 * p) += a.self()[p] * Eigen::Matrix3d::Identity();
  const PairSchedule& pattern = *a.pattern();
  for (std::size_t e = 0; e < pattern.size(); ++e) {
    const Eigen::Matrix3d w = a.pair(e).dense();
    const int i = pattern.a()[e], j = pattern.b()[e];
    dense.block<3, 3>(3 * i, 3 * i) += w, dense.block<3, 3>(3 * j, 3 * j) += w;
    dense.block<3, 3>(3 * i, 3 * j) -= w, dense.block<3, 3>(3 * j, 3 * i) -= w;
  }
  for (const StencilBlock& b : a.stencils())
    for (int i = 0; i < b.stencil.size; ++i)
      for (int j = 0; j < b.stencil.size; ++j)
        dense.block<3, 3>(3 * b.stencil.particle[i], 3 * b.stencil.particle[j]) +=
            b.stencil.w[i] * b.stencil.w[j] * b.block.dense();
  return dense;
}

}  // namespace wobble::testing
