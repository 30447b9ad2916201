// SPDX-License-Identifier: Apache-2.0
#include "forces/PlanePenalty.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "forces/SmoothedPenalty.h"

namespace tissuesim {

PlanePenalty::PlanePenalty(std::vector<CapsulePenalty::Point> points, const Eigen::Vector3d& up,
                           double height_m)
    : m_points(std::move(points)), m_up(up), m_height_m(height_m) {
  const double length = up.norm();
  if (!(length > 0.0) || !std::isfinite(length) || !std::isfinite(height_m))
    throw std::invalid_argument(
        "PlanePenalty: the plane's normal and height must be finite and "
        "the normal non-zero");
  m_up /= length;
}

Eigen::Vector3d PlanePenalty::support_N(const Eigen::Matrix3Xd& x) const {
  double total = 0.0;
  for (const CapsulePenalty::Point& point : m_points) {
    total -= point.stiffness_N_m * smoothedPenalty(m_up.dot(point.position(x)) - m_height_m).slope;
  }
  return total * m_up;
}

double PlanePenalty::maxPenetration_m(const Eigen::Matrix3Xd& x) const {
  double deepest = 0.0;
  for (const CapsulePenalty::Point& point : m_points)
    deepest = std::max(deepest, m_height_m - m_up.dot(point.position(x)));
  return deepest;
}

double PlanePenalty::add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                         std::vector<Eigen::Triplet<double>>* hessian) const {
  double energy = 0.0;
  const Eigen::Matrix3d upUp = m_up * m_up.transpose();
  for (const CapsulePenalty::Point& point : m_points) {
    const PenaltyTerms terms = smoothedPenalty(m_up.dot(point.position(x)) - m_height_m);
    if (terms.curvature == 0.0) continue;
    const double k = point.stiffness_N_m;
    energy += k * terms.energy;
    for (std::size_t i = 0; i < 3; ++i) {
      const double wi = point.weights[static_cast<Eigen::Index>(i)];
      if (wi == 0.0) continue;
      if (gradient != nullptr) gradient->col(point.nodes[i]) += wi * k * terms.slope * m_up;
      if (hessian == nullptr) continue;
      for (std::size_t j = 0; j < 3; ++j) {
        const double wj = point.weights[static_cast<Eigen::Index>(j)];
        if (wj == 0.0) continue;
        const Eigen::Matrix3d block = (wi * wj * k * terms.curvature) * upUp;
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c)
            hessian->emplace_back(3 * point.nodes[i] + r, 3 * point.nodes[j] + c, block(r, c));
        }
      }
    }
  }
  return energy;
}

}  // namespace tissuesim
