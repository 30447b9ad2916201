// SPDX-License-Identifier: Apache-2.0
#include "analysis/GoodnessOfFit.h"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace tissuesim {

double coefficientOfDetermination(std::span<const double> reference,
                                  std::span<const double> model) {
  if (reference.size() != model.size() || reference.size() < 2) {
    throw std::invalid_argument("R^2 needs two curves of equal length with at least 2 points");
  }
  const double mean = std::accumulate(reference.begin(), reference.end(), 0.0) /
                      static_cast<double>(reference.size());
  double residual = 0.0;
  double total = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    residual += (reference[i] - model[i]) * (reference[i] - model[i]);
    total += (reference[i] - mean) * (reference[i] - mean);
  }
  if (total == 0.0) return residual == 0.0 ? 1.0 : -std::numeric_limits<double>::infinity();
  return 1.0 - residual / total;
}

double slopeThroughOrigin(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size() || x.empty()) {
    throw std::invalid_argument("a least-squares slope needs two series of equal, non-zero length");
  }
  const double xy = std::inner_product(x.begin(), x.end(), y.begin(), 0.0);
  const double xx = std::inner_product(x.begin(), x.end(), x.begin(), 0.0);
  if (xx == 0.0) throw std::invalid_argument("a least-squares slope needs some x != 0");
  return xy / xx;
}

}  // namespace tissuesim
