#pragma once
// The grasper: while the instrument's jaws are closed, the surface nodes that were within reach
// of the tip when they closed are held at their offsets from the tip by stiff damped springs
//   f_i = k (tip + R o_i - x_i) - c v_i
// (explicit in time, with k below the stability bound), and the instrument feels minus their
// sum. R turns the shaft's direction when the jaws closed onto its direction now (the shortest
// rotation between the two), so tilting the instrument swings the held tissue round the tip.
// The shaft's roll is not part of the pose, so turning the tool about its own axis does not.
// Opening the jaws releases them.

#include <vector>

#include "sim/ContactProvider.h"

namespace tissuesim {

class Grasp {
 public:
  /// @param reach_m nodes within this distance of the tip are caught when the jaws close.
  Grasp(std::vector<int> candidateNodes, double reach_m, double stiffness_N_m = 200.0,
        double damping_N_s_m = 0.5)
      : m_candidates(std::move(candidateNodes)),
        m_reach_m(reach_m),
        m_stiffness(stiffness_N_m),
        m_damping(damping_N_s_m) {}

  /// Captures on closing, releases on opening, and adds the holding forces.
  void apply(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, const InstrumentPose& pose,
             Eigen::Matrix3Xd& forces, ContactResult& result);

  const std::vector<int>& heldNodes() const { return m_held; }
  void release() {
    m_held.clear();
    m_wasClosed = false;
  }

 private:
  std::vector<int> m_candidates;
  double m_reach_m;
  double m_stiffness;
  double m_damping;
  bool m_wasClosed = false;
  std::vector<int> m_held;
  std::vector<Eigen::Vector3d> m_offsets;  ///< o_i, world frame at the closing
  Eigen::Vector3d m_closingDirection = Eigen::Vector3d::UnitZ();
};

}  // namespace tissuesim
