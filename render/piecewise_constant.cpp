// Piecewise-constant distributions (piecewise_constant.h).
#include "render/piecewise_constant.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wobble::render {

PiecewiseConstant1D::PiecewiseConstant1D(std::span<const float> weights)
    : weight_(weights.begin(), weights.end()), cdf_(weights.size() + 1, 0.0f) {
  std::vector<double> running(weights.size() + 1, 0.0);
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!(weights[i] >= 0) || !std::isfinite(weights[i]))
      throw std::invalid_argument("PiecewiseConstant1D: weights must be finite and >= 0");
    running[i + 1] = running[i] + weights[i];
  }
  sum_ = running.back();
  if (sum_ > 0)
    for (std::size_t i = 1; i < running.size(); ++i) cdf_[i] = float(running[i] / sum_);
  cdf_.back() = 1.0f;
}

float PiecewiseConstant1D::probability(int bin) const { return sum_ > 0 ? float(weight_[bin] / sum_) : 0.0f; }

int PiecewiseConstant1D::sample(float u, float& fraction) const {
  const int n = size();
  // The last bin whose start is <= u; a bin of weight 0 has the same start as the next and is passed over.
  const int bin = std::clamp(int(std::upper_bound(cdf_.begin() + 1, cdf_.end(), u) - (cdf_.begin() + 1)), 0, n - 1);
  const float width = cdf_[bin + 1] - cdf_[bin];
  fraction = width > 0 ? std::clamp((u - cdf_[bin]) / width, 0.0f, std::nextafter(1.0f, 0.0f)) : 0.5f;
  return bin;
}

PiecewiseConstant2D::PiecewiseConstant2D(std::span<const float> weights, int columns, int rows) {
  if (columns < 1 || rows < 1 || weights.size() != std::size_t(columns) * std::size_t(rows))
    throw std::invalid_argument("PiecewiseConstant2D: weights must be columns x rows");
  conditional_.reserve(rows);
  std::vector<float> row_sums(rows);
  for (int r = 0; r < rows; ++r) {
    conditional_.emplace_back(weights.subspan(std::size_t(r) * columns, columns));
    row_sums[r] = float(conditional_.back().sum());
  }
  marginal_ = PiecewiseConstant1D(row_sums);
}

float PiecewiseConstant2D::probability(int column, int row) const {
  return marginal_.probability(row) * conditional_[row].probability(column);
}

void PiecewiseConstant2D::sample(float u1, float u2, int& column, int& row, float& column_fraction,
                                 float& row_fraction) const {
  row = marginal_.sample(u1, row_fraction);
  column = conditional_[row].sample(u2, column_fraction);
}

}  // namespace wobble::render
