// SPDX-License-Identifier: Apache-2.0
#include "sim/Grasp.h"

namespace tissuesim {

void Grasp::apply(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                  PenaltyContactSet& contacts) {
  if (pose.isGrasping && !m_wasClosed) {
    m_held.clear();
    m_offsets.clear();
    m_closingDirection = pose.direction;
    for (const int node : m_candidates) {
      const Eigen::Vector3d offset = x.col(node) - pose.tip_m;
      if (offset.norm() <= m_reach_m) {
        m_held.push_back(node);
        m_offsets.push_back(offset);
      }
    }
  } else if (!pose.isGrasping && m_wasClosed) {
    m_held.clear();
    m_offsets.clear();
  }
  m_wasClosed = pose.isGrasping;
  if (m_held.empty()) return;
  const Eigen::Matrix3d turn =
      Eigen::Quaterniond::FromTwoVectors(m_closingDirection, pose.direction).toRotationMatrix();
  PenaltyContact spring;
  spring.weights = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  spring.stiffness_N_m = m_stiffness;
  spring.damping_N_s_m = m_damping;
  spring.isTether = true;
  for (std::size_t i = 0; i < m_held.size(); ++i) {
    spring.nodes.fill(m_held[i]);
    const Eigen::Vector3d target = pose.tip_m + turn * m_offsets[i];
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        spring.normal = sign * Eigen::Vector3d::Unit(axis);
        spring.offset_m = sign * target[axis];
        contacts.add(spring);
      }
    }
  }
}

}  // namespace tissuesim
