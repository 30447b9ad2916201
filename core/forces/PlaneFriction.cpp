// SPDX-License-Identifier: Apache-2.0
#include "forces/PlaneFriction.h"

#include <cmath>

namespace tissuesim {

PlaneFriction::PlaneFriction(std::vector<CarriedSurfacePoint> points, const Eigen::Vector3d& up,
                             double height_m, double coefficient, Eigen::Index nodeCount)
    : m_points(std::move(points)),
      m_up(up.normalized()),
      m_height_m(height_m),
      m_coefficient(coefficient),
      m_anchors(m_points.size()) {
  m_ties.reserve(m_points.size());
  for (std::size_t slot = 0; slot < 2; ++slot) {
    m_terms[slot].reserve(2 * m_points.size());
    m_diagonals[slot].resize(nodeCount, 2 * m_points.size());
  }
}

void PlaneFriction::beginStep(const Eigen::Matrix3Xd& x) {
  m_ties.clear();
  for (std::size_t p = 0; p < m_points.size(); ++p) {
    const Anchor& anchor = m_anchors[p];
    if (!(anchor.limit_N > 0.0)) continue;
    const CarriedSurfacePoint& point = m_points[p];
    const Eigen::Vector3d offset = point.drawn(x) - point.load(x) - anchor.position_m;
    m_ties.push_back({static_cast<int>(p), offset - m_up.dot(offset) * m_up});
  }
}

void PlaneFriction::acceptStep(const Eigen::Matrix3Xd& x) {
  for (std::size_t p = 0; p < m_points.size(); ++p) {
    const CarriedSurfacePoint& point = m_points[p];
    Anchor& anchor = m_anchors[p];
    const Eigen::Vector3d drawn = point.drawn(x);
    const double sink_m = m_height_m - m_up.dot(drawn);
    if (!(sink_m > 0.0)) {
      anchor.limit_N = 0.0;  // off the plane: free
      continue;
    }
    const Eigen::Vector3d onPlane = drawn + sink_m * m_up;
    const bool wasAnchored = anchor.limit_N > 0.0;
    anchor.limit_N = m_coefficient * point.stiffness_N_m * sink_m;
    if (!wasAnchored) {
      anchor.position_m = onPlane;  // came down: sticks where it touched
      continue;
    }
    // Slid past the cone (beyond the stick spring's reach r = L / k): the anchor is dragged
    // along to r behind the point.
    const Eigen::Vector3d slip = onPlane - anchor.position_m;
    const double reach_m = anchor.limit_N / point.stiffness_N_m;
    const double length_m = slip.norm();
    if (length_m > reach_m) anchor.position_m = onPlane - (reach_m / length_m) * slip;
  }
}

void PlaneFriction::releaseAnchors() {
  for (Anchor& anchor : m_anchors) anchor.limit_N = 0.0;
  m_ties.clear();
}

void PlaneFriction::restoreAnchors(const std::vector<Anchor>& anchors) {
  m_anchors = anchors;  // same size: no allocation
  m_ties.clear();
}

Eigen::Vector3d PlaneFriction::force_N(const Eigen::Matrix3Xd& x) const {
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const Tie& tie : m_ties) {
    const Anchor& anchor = m_anchors[static_cast<std::size_t>(tie.point)];
    const double k = m_points[static_cast<std::size_t>(tie.point)].stiffness_N_m;
    const Eigen::Vector3d g = slip(tie, x);
    const double length_m = g.norm();
    total -= k * length_m <= anchor.limit_N ? Eigen::Vector3d(k * g)
                                            : Eigen::Vector3d(anchor.limit_N / length_m * g);
  }
  return total;
}

int PlaneFriction::slidingCount(const Eigen::Matrix3Xd& x) const {
  int count = 0;
  for (const Tie& tie : m_ties) {
    const double k = m_points[static_cast<std::size_t>(tie.point)].stiffness_N_m;
    if (k * slip(tie, x).norm() > m_anchors[static_cast<std::size_t>(tie.point)].limit_N) ++count;
  }
  return count;
}

double PlaneFriction::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  for (const Tie& tie : m_ties) {
    const double limit = m_anchors[static_cast<std::size_t>(tie.point)].limit_N;
    const double k = m_points[static_cast<std::size_t>(tie.point)].stiffness_N_m;
    const double length_m = slip(tie, x).norm();
    const double reach_m = limit / k;
    energy +=
        length_m <= reach_m ? 0.5 * k * length_m * length_m : limit * (length_m - 0.5 * reach_m);
  }
  return energy;
}

void PlaneFriction::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                              ForceReport&) const {
  const bool keepsStiffness = pass.stiffness != StiffnessSlot::None;
  const auto slot = static_cast<std::size_t>(
      pass.stiffness == StiffnessSlot::Current ? m_current : m_current ^ 1);
  std::vector<RankOneTerm>& terms = m_terms[slot];
  if (keepsStiffness) terms.clear();
  // The stick branch's plane, spanned by two unit tangents.
  const Eigen::Vector3d t1 = m_up.unitOrthogonal();
  const Eigen::Vector3d t2 = m_up.cross(t1);
  for (const Tie& tie : m_ties) {
    const CarriedSurfacePoint& point = m_points[static_cast<std::size_t>(tie.point)];
    const double limit = m_anchors[static_cast<std::size_t>(tie.point)].limit_N;
    const double k = point.stiffness_N_m;
    const Eigen::Vector3d g = slip(tie, x);
    const double length_m = g.norm();
    const bool sticks = k * length_m <= limit;
    const Eigen::Vector3d force =
        sticks ? Eigen::Vector3d(-k * g) : Eigen::Vector3d(-(limit / length_m) * g);
    for (std::size_t n = 0; n < kMaxTermNodes; ++n)
      f.col(point.nodes[n]) += point.carried[static_cast<Eigen::Index>(n)] * force;
    // Gershgorin: node n's rows of K_p w w^T sum to at most k w_n (the weights sum to 1).
    if (pass.nodeStiffness != nullptr) {
      for (std::size_t n = 0; n < kMaxTermNodes; ++n)
        (*pass.nodeStiffness)[point.nodes[n]] += k * point.carried[static_cast<Eigen::Index>(n)];
    }
    if (!keepsStiffness) continue;
    const auto addTerm = [&](const Eigen::Vector3d& direction, double stiffness_N_m) {
      terms.push_back(
          pointTerm(point.nodes, point.carried, direction, stiffness_N_m, pass.fixedDofs));
    };
    if (sticks) {
      addTerm(t1, k);
      addTerm(t2, k);
    } else {
      addTerm(m_up.cross(g / length_m), limit / length_m);
    }
  }
  if (keepsStiffness) m_diagonals[slot].set(terms);
}

void PlaneFriction::addStiffnessProduct(int part, const double* x, double* y) const {
  addRankOneProducts(m_terms[static_cast<std::size_t>(m_current)],
                     m_bounds[static_cast<std::size_t>(part)],
                     m_bounds[static_cast<std::size_t>(part) + 1], x, y);
}

void PlaneFriction::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  if (const Eigen::Matrix3d* diagonal = m_diagonals[static_cast<std::size_t>(m_current)].at(j))
    block += *diagonal;
}

void PlaneFriction::addStiffness(NodeBlockMatrix& matrix) const {
  addRankOneTerms(m_terms[static_cast<std::size_t>(m_current)], matrix);
}

}  // namespace tissuesim
