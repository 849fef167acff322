#include "app/study/order_fit.h"

#include <cmath>
#include <limits>

#include "sim/integrators/integrator.h"

namespace wobble {

int convergenceOrder(std::string_view integrator) { return integratorTraits(integrator).order; }

double fitOrder(const std::vector<double>& step, const std::vector<double>& error) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < step.size() && i < error.size(); ++i) {
    if (!(step[i] > 0) || !(error[i] > 0) || !std::isfinite(step[i]) || !std::isfinite(error[i])) continue;
    const double lx = std::log(step[i]), ly = std::log(error[i]);
    n += 1;
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || denominator <= 0) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / denominator;
}

}  // namespace wobble
