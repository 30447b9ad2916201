#include "integrators/PenaltyContacts.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {

void PenaltyContactSet::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces) const {
  for (const PenaltyContact& c : m_contacts) {
    const double delta = c.penetration(x);
    if (!(delta > 0.0) && !std::isnan(delta)) continue;  // a NaN goes through, to be caught
    const Eigen::Vector3d push = -c.stiffness_N_m * delta * c.normal;
    for (int k = 0; k < 3; ++k) forces.col(c.nodes[static_cast<std::size_t>(k)]) += c.weights[k] * push;
  }
}

void PenaltyContactSet::addStiffness(const Eigen::Matrix3Xd& x, NodeBlockMatrix& stiffness) const {
  for (const PenaltyContact& c : m_contacts) {
    if (!(c.penetration(x) > 0.0)) continue;
    const Eigen::Matrix3d nn = c.stiffness_N_m * c.normal * c.normal.transpose();
    for (int i = 0; i < 3; ++i) {
      if (c.weights[i] == 0.0) continue;
      for (int j = 0; j < 3; ++j) {
        if (c.weights[j] == 0.0) continue;
        stiffness.addBlock(c.nodes[static_cast<std::size_t>(i)], c.nodes[static_cast<std::size_t>(j)],
                           (c.weights[i] * c.weights[j]) * nn);
      }
    }
  }
}

void PenaltyContactSet::addNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::VectorXd& nodeStiffness) const {
  for (const PenaltyContact& c : m_contacts) {
    if (!(c.penetration(x) > 0.0)) continue;
    const double sum = c.weights.sum();
    for (int k = 0; k < 3; ++k) {
      nodeStiffness[c.nodes[static_cast<std::size_t>(k)]] += c.stiffness_N_m * c.weights[k] * sum;
    }
  }
}

ContactResult PenaltyContactSet::reaction(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& tip_m) const {
  ContactResult result;
  for (const PenaltyContact& c : m_contacts) {
    const double delta = c.penetration(x);
    if (!(delta > 0.0)) continue;
    const Eigen::Vector3d onTool = c.stiffness_N_m * delta * c.normal;
    result.toolForce_N += onTool;
    result.toolTorque_Nm += (c.point(x) - tip_m).cross(onTool);
    result.maxPenetration_m = std::max(result.maxPenetration_m, delta);
    ++result.contactNodes;
  }
  return result;
}

}  // namespace tissuesim
