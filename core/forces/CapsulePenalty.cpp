// SPDX-License-Identifier: Apache-2.0
#include "forces/CapsulePenalty.h"

#include <algorithm>
#include <stdexcept>

#include "forces/CapsuleGap.h"
#include "forces/SmoothedPenalty.h"
#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

CapsulePenalty::CapsulePenalty(std::vector<Point> points) : m_points(std::move(points)) {
  for (auto& slot : m_slots) slot.reserve(m_points.size());
}

double CapsulePenalty::gap(const Eigen::Vector3d& s, Eigen::Vector3d& n) const {
  const CapsuleGap at = capsuleGap(s, tip_m, top_m, radius_m);
  n = at.normal;
  return at.gap_m;
}

double CapsulePenalty::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  Eigen::Vector3d n;
  for (const Point& point : m_points) {
    energy += point.stiffness_N_m * smoothedPenalty(gap(point.position(x), n)).energy;
  }
  return energy;
}

Eigen::Vector3d CapsulePenalty::reaction(const Eigen::Matrix3Xd& x) const {
  Eigen::Vector3d onCapsule = Eigen::Vector3d::Zero();
  Eigen::Vector3d n;
  for (const Point& point : m_points) {
    // Minus the force on the surface.
    onCapsule += point.stiffness_N_m * smoothedPenalty(gap(point.position(x), n)).slope * n;
  }
  return onCapsule;
}

void CapsulePenalty::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                               const ForcePass& pass, ForceReport&) const {
  std::vector<Active>* slot = nullptr;
  if (pass.stiffness == StiffnessSlot::Current)
    slot = &m_slots[static_cast<std::size_t>(m_current)];
  if (pass.stiffness == StiffnessSlot::Trial)
    slot = &m_slots[static_cast<std::size_t>(m_current ^ 1)];
  if (slot != nullptr) slot->clear();
  Eigen::Vector3d n;
  for (std::size_t p = 0; p < m_points.size(); ++p) {
    const Point& point = m_points[p];
    const PenaltyTerms terms = smoothedPenalty(gap(point.position(x), n));
    if (terms.curvature == 0.0) continue;
    const double k = point.stiffness_N_m;
    for (std::size_t i = 0; i < 3; ++i) {
      const double w = point.weights[static_cast<Eigen::Index>(i)];
      f.col(point.nodes[i]) -= w * k * terms.slope * n;
      if (pass.nodeStiffness != nullptr) (*pass.nodeStiffness)[point.nodes[i]] += w * k;
    }
    if (slot != nullptr) slot->push_back({static_cast<int>(p), terms.curvature * k, n});
  }
}

void CapsulePenalty::addStiffnessProduct(int part, const double* x, double* y) const {
  const Eigen::Index first = m_bounds[static_cast<std::size_t>(part)];
  const Eigen::Index last = m_bounds[static_cast<std::size_t>(part) + 1];
  for (const Active& active : m_slots[static_cast<std::size_t>(m_current)]) {
    const Point& point = m_points[static_cast<std::size_t>(active.point)];
    double nx = 0.0;  // n . (sum_k w_k x_k)
    for (std::size_t i = 0; i < 3; ++i) {
      nx += point.weights[static_cast<Eigen::Index>(i)] *
            active.n.dot(Eigen::Map<const Eigen::Vector3d>(x + 3 * point.nodes[i]));
    }
    for (std::size_t i = 0; i < 3; ++i) {
      const int node = point.nodes[i];
      if (node < first || node >= last) continue;
      Eigen::Map<Eigen::Vector3d>(y + 3 * node) +=
          (point.weights[static_cast<Eigen::Index>(i)] * active.stiffness_N_m * nx) * active.n;
    }
  }
}

void CapsulePenalty::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  for (const Active& active : m_slots[static_cast<std::size_t>(m_current)]) {
    const Point& point = m_points[static_cast<std::size_t>(active.point)];
    double w = 0.0;  // node j's weight, summed where a slot repeats it
    for (std::size_t i = 0; i < 3; ++i) {
      if (point.nodes[i] == j) w += point.weights[static_cast<Eigen::Index>(i)];
    }
    if (w != 0.0) block += (w * w * active.stiffness_N_m) * active.n * active.n.transpose();
  }
}

void CapsulePenalty::addStiffness(NodeBlockMatrix& matrix) const {
  for (const Active& active : m_slots[static_cast<std::size_t>(m_current)]) {
    const Point& point = m_points[static_cast<std::size_t>(active.point)];
    const Eigen::Matrix3d knn = active.stiffness_N_m * active.n * active.n.transpose();
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        const double ww = point.weights[static_cast<Eigen::Index>(i)] *
                          point.weights[static_cast<Eigen::Index>(j)];
        if (ww != 0.0) matrix.addBlock(point.nodes[i], point.nodes[j], ww * knn);
      }
    }
  }
}

double CapsulePenalty::add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                           std::vector<Eigen::Triplet<double>>* hessian) const {
  double energy = 0.0;
  Eigen::Vector3d n;
  for (const Point& point : m_points) {
    const PenaltyTerms terms = smoothedPenalty(gap(point.position(x), n));
    if (terms.curvature == 0.0) continue;
    energy += point.stiffness_N_m * terms.energy;
    point.addPenalty(terms, n, gradient, hessian);
  }
  return energy;
}

void CapsulePenalty::Point::addPenalty(const PenaltyTerms& terms, const Eigen::Vector3d& n,
                                       Eigen::Matrix3Xd* gradient,
                                       std::vector<Eigen::Triplet<double>>* hessian) const {
  const double k = stiffness_N_m;
  for (std::size_t i = 0; i < 3; ++i) {
    const double wi = weights[static_cast<Eigen::Index>(i)];
    if (wi == 0.0) continue;
    if (gradient != nullptr) gradient->col(nodes[i]) += wi * k * terms.slope * n;
    if (hessian == nullptr) continue;
    for (std::size_t j = 0; j < 3; ++j) {
      const double wj = weights[static_cast<Eigen::Index>(j)];
      if (wj == 0.0) continue;
      const Eigen::Matrix3d block = wi * wj * k * terms.curvature * n * n.transpose();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
          hessian->emplace_back(3 * nodes[i] + r, 3 * nodes[j] + c, block(r, c));
      }
    }
  }
}

}  // namespace tissuesim
