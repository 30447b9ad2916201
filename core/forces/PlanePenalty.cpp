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
  for (const CapsulePenalty::Point& point : m_points) {
    const PenaltyTerms terms = smoothedPenalty(m_up.dot(point.position(x)) - m_height_m);
    if (terms.curvature == 0.0) continue;
    energy += point.stiffness_N_m * terms.energy;
    point.addPenalty(terms, m_up, gradient, hessian);
  }
  return energy;
}

}  // namespace tissuesim
