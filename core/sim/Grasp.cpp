#include "sim/Grasp.h"

namespace tissuesim {

void Grasp::apply(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, const InstrumentPose& pose,
                  Eigen::Matrix3Xd& forces, ContactResult& result) {
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
  for (std::size_t i = 0; i < m_held.size(); ++i) {
    const int node = m_held[i];
    const Eigen::Vector3d f =
        m_stiffness * (pose.tip_m + turn * m_offsets[i] - x.col(node)) - m_damping * v.col(node);
    forces.col(node) += f;
    result.toolForce_N -= f;
    result.toolTorque_Nm -= (x.col(node) - pose.tip_m).cross(f);
  }
}

}  // namespace tissuesim
