// SPDX-License-Identifier: Apache-2.0
#include "forces/PenaltyContacts.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {

void PenaltyContactSet::reserve(std::size_t count) {
  m_contacts.reserve(count);
  for (std::vector<RankOneTerm>& terms : m_terms) terms.reserve(count);
}

void PenaltyContactSet::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                  const ForcePass& pass, ForceReport&) const {
  addForces(x, f);
  if (pass.nodeStiffness != nullptr) {
    // Gershgorin: node k's rows of k w w^T n n^T sum to at most k w_k (the weights sum to 1).
    for (const PenaltyContact& c : m_contacts) {
      if (!(c.penetration(x) > 0.0)) continue;
      for (std::size_t k = 0; k < kMaxTermNodes; ++k)
        (*pass.nodeStiffness)[c.nodes[k]] +=
            c.stiffness_N_m * c.weights[static_cast<Eigen::Index>(k)];
    }
  }
  if (pass.stiffness == StiffnessSlot::None) return;
  const auto slot = static_cast<std::size_t>(
      pass.stiffness == StiffnessSlot::Current ? m_current : m_current ^ 1);
  m_instrumentTermCount[slot] = collectTerms(x, pass.fixedDofs, m_terms[slot]);
  if (m_hasDiagonals) m_diagonals[slot].set(m_terms[slot]);
}

void PenaltyContactSet::prepareProducts(const PartBounds& bounds) {
  if (m_hasDiagonals && bounds == m_bounds) return;
  m_bounds = bounds;
  for (std::size_t slot = 0; slot < 2; ++slot) {
    m_diagonals[slot].resize(bounds[kParts], kReservedContacts);
    m_diagonals[slot].set(m_terms[slot]);  // a pass before this call kept terms already
  }
  m_hasDiagonals = true;
}

void PenaltyContactSet::addStiffnessProduct(int part, const double* x, double* y) const {
  addRankOneProducts(m_terms[static_cast<std::size_t>(m_current)],
                     m_bounds[static_cast<std::size_t>(part)],
                     m_bounds[static_cast<std::size_t>(part) + 1], x, y);
}

void PenaltyContactSet::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  if (const Eigen::Matrix3d* diagonal = m_diagonals[static_cast<std::size_t>(m_current)].at(j))
    block += *diagonal;
}

void PenaltyContactSet::addStiffness(NodeBlockMatrix& matrix) const {
  addRankOneTerms(m_terms[static_cast<std::size_t>(m_current)], matrix);
}

double PenaltyContactSet::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  for (const PenaltyContact& c : m_contacts) {
    const double delta = c.penetration(x);
    if (delta > 0.0) energy += 0.5 * c.stiffness_N_m * delta * delta;
  }
  return energy;
}

void PenaltyContactSet::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces) const {
  for (const PenaltyContact& c : m_contacts) {
    const double delta = c.penetration(x);
    if (!(delta > 0.0) && !std::isnan(delta)) continue;  // a NaN goes through, to be caught
    const Eigen::Vector3d push = -c.stiffness_N_m * delta * c.normal;
    for (std::size_t k = 0; k < kMaxTermNodes; ++k)
      forces.col(c.nodes[k]) += c.weights[static_cast<Eigen::Index>(k)] * push;
  }
}

Eigen::Vector3d PenaltyContactSet::applyImpulses(const Eigen::Matrix3Xd& x,
                                                 const Eigen::VectorXd& mass_kg,
                                                 const std::vector<char>& isFixed, double h,
                                                 Eigen::Matrix3Xd& v) const {
  Eigen::Vector3d onTool_Ns = Eigen::Vector3d::Zero();
  for (const PenaltyContact& c : m_contacts) {
    std::array<double, kMaxTermNodes> inverseMass{};
    double compliance = 0.0;  // 1 / m_e = sum_k w_k^2 / m_k
    for (int k = 0; k < static_cast<int>(kMaxTermNodes); ++k) {
      const int node = c.nodes[static_cast<std::size_t>(k)];
      const auto dof = static_cast<std::size_t>(3 * node);
      const bool isHeld = isFixed[dof] != 0 || isFixed[dof + 1] != 0 || isFixed[dof + 2] != 0;
      inverseMass[static_cast<std::size_t>(k)] = isHeld ? 0.0 : 1.0 / mass_kg[node];
      compliance += c.weights[k] * c.weights[k] * inverseMass[static_cast<std::size_t>(k)];
    }
    if (!(compliance > 0.0)) continue;
    const double delta = c.penetration(x);
    const double u = c.normal.dot(c.point(v));
    const double gain = h * h * c.stiffness_N_m + h * c.damping_N_s_m;
    const double lambda = (h * c.stiffness_N_m * delta + gain * u) / (1.0 + gain * compliance);
    if (!(lambda > 0.0) && !std::isnan(lambda))
      continue;  // push only; a NaN goes through, to be caught
    for (int k = 0; k < static_cast<int>(kMaxTermNodes); ++k) {
      v.col(c.nodes[static_cast<std::size_t>(k)]) -=
          (c.weights[k] * inverseMass[static_cast<std::size_t>(k)] * lambda) * c.normal;
    }
    if (!c.isSupport) onTool_Ns += lambda * c.normal;
  }
  return onTool_Ns;
}

void PenaltyContactSet::addStiffness(const Eigen::Matrix3Xd& x, NodeBlockMatrix& stiffness) const {
  for (const PenaltyContact& c : m_contacts) {
    if (!(c.penetration(x) > 0.0)) continue;
    const Eigen::Matrix3d nn = c.stiffness_N_m * c.normal * c.normal.transpose();
    for (int i = 0; i < static_cast<int>(kMaxTermNodes); ++i) {
      if (c.weights[i] == 0.0) continue;
      for (int j = 0; j < static_cast<int>(kMaxTermNodes); ++j) {
        if (c.weights[j] == 0.0) continue;
        stiffness.addBlock(c.nodes[static_cast<std::size_t>(i)],
                           c.nodes[static_cast<std::size_t>(j)],
                           (c.weights[i] * c.weights[j]) * nn);
      }
    }
  }
}

std::size_t PenaltyContactSet::rankOneTerms(const Eigen::Matrix3Xd& x,
                                            const std::vector<char>& isFixed,
                                            std::vector<RankOneTerm>& terms) const {
  return collectTerms(x, &isFixed, terms);
}

std::size_t PenaltyContactSet::collectTerms(const Eigen::Matrix3Xd& x,
                                            const std::vector<char>* isFixed,
                                            std::vector<RankOneTerm>& terms) const {
  terms.clear();
  std::size_t instrumentCount = 0;
  for (const bool isSupportPass : {false, true}) {
    for (const PenaltyContact& c : m_contacts) {
      if (c.isSupport != isSupportPass) continue;
      if (!(c.penetration(x) > 0.0)) continue;  // as addStiffness
      terms.push_back(pointTerm(c.nodes, c.weights, c.normal, c.stiffness_N_m, isFixed));
    }
    if (!isSupportPass) instrumentCount = terms.size();
  }
  return instrumentCount;
}

ContactResult PenaltyContactSet::reaction(const Eigen::Matrix3Xd& x,
                                          const Eigen::Vector3d& tip_m) const {
  ContactResult result;
  for (const PenaltyContact& c : m_contacts) {
    if (c.isSupport) continue;
    const double delta = c.penetration(x);
    if (!(delta > 0.0)) continue;
    const Eigen::Vector3d onTool = c.stiffness_N_m * delta * c.normal;
    result.toolForce_N += onTool;
    result.toolTorque_Nm += (c.point(x) - tip_m).cross(onTool);
    if (c.isTether) continue;
    result.maxPenetration_m = std::max(result.maxPenetration_m, delta);
    ++result.contactNodes;
  }
  return result;
}

}  // namespace tissuesim
