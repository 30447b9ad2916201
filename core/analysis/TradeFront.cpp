// SPDX-License-Identifier: Apache-2.0
#include "analysis/TradeFront.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace tissuesim {

std::vector<int> paretoFront(const std::vector<double>& cost, const std::vector<double>& error,
                             double errorResolution) {
  if (cost.size() != error.size())
    throw std::invalid_argument("paretoFront: cost and error differ in length");
  std::vector<int> order;
  for (std::size_t i = 0; i < cost.size(); ++i) {
    if (std::isfinite(cost[i]) && std::isfinite(error[i])) order.push_back(static_cast<int>(i));
  }
  // By cost, ties by error: a point is on the front when its error is below every cheaper one's.
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto i = static_cast<std::size_t>(a);
    const auto j = static_cast<std::size_t>(b);
    return cost[i] < cost[j] || (cost[i] == cost[j] && error[i] < error[j]);
  });
  std::vector<int> front;
  double best = std::numeric_limits<double>::infinity();
  for (const int index : order) {
    const double e = error[static_cast<std::size_t>(index)];
    if (e < best - errorResolution) {
      front.push_back(index);
      best = e;
    }
  }
  return front;
}

double powerLawExponent(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> logX;
  std::vector<double> logY;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (x[i] > 0.0 && y[i] > 0.0 && std::isfinite(x[i]) && std::isfinite(y[i])) {
      logX.push_back(std::log(x[i]));
      logY.push_back(std::log(y[i]));
    }
  }
  const auto n = static_cast<double>(logX.size());
  if (logX.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const double meanX = std::accumulate(logX.begin(), logX.end(), 0.0) / n;
  const double meanY = std::accumulate(logY.begin(), logY.end(), 0.0) / n;
  double sxx = 0.0;
  double sxy = 0.0;
  for (std::size_t i = 0; i < logX.size(); ++i) {
    sxx += (logX[i] - meanX) * (logX[i] - meanX);
    sxy += (logX[i] - meanX) * (logY[i] - meanY);
  }
  if (!(sxx > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return sxy / sxx;
}

}  // namespace tissuesim
