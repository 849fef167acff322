// PiecewiseConstant1D and PiecewiseConstant2D: draw a bin of a table of non-negative weights with probability in
// proportion to its weight, by inverting the table's cumulative sum, as pbrt-v4's PiecewiseConstant1D/2D (Pharr,
// Jakob, Humphreys, "Physically Based Rendering", 4th ed., 2023, sections A.4 and A.5; 2D: a marginal over the rows,
// then the chosen row's conditional over its columns). Besides the bin, sample() returns where in the bin u fell, as a
// fraction in [0, 1): the caller places its point there, so stratified or low-discrepancy u stay well spread.
// Bins of weight 0 are never drawn. The sums are accumulated in double, so tables of millions of bins keep their
// small weights.
#pragma once
#include <span>
#include <vector>

namespace wobble::render {

class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  explicit PiecewiseConstant1D(std::span<const float> weights);  // each finite and >= 0

  int size() const { return int(weight_.size()); }
  double sum() const { return sum_; }  // of the weights; 0: nothing to draw
  float probability(int bin) const;    // weight / sum (0 when the sum is)
  // The bin whose cumulative interval holds u in [0, 1), and u's fraction of that interval.
  int sample(float u, float& fraction) const;

 private:
  std::vector<float> weight_, cdf_;  // cdf_: size + 1 entries from 0 to exactly 1
  double sum_ = 0;
};

class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  // weights: rows x columns, row after row.
  PiecewiseConstant2D(std::span<const float> weights, int columns, int rows);

  double sum() const { return marginal_.sum(); }
  float probability(int column, int row) const;
  // u1 picks the row, u2 the column; fractions as PiecewiseConstant1D::sample.
  void sample(float u1, float u2, int& column, int& row, float& column_fraction, float& row_fraction) const;

 private:
  std::vector<PiecewiseConstant1D> conditional_;  // one per row
  PiecewiseConstant1D marginal_;                  // the rows' sums
};

}  // namespace wobble::render
