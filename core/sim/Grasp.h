// SPDX-License-Identifier: Apache-2.0
#pragma once
// The grasper: while the instrument's jaws are closed, the surface nodes that were within reach
// of the tip when they closed are held at their offsets from the tip, each by a stiff spring
//   f_i = k (t_i - x_i),   t_i = tip + R o_i   (N; k in N/m, positions in m)
// and the instrument feels minus their sum. R turns the shaft's direction when the jaws closed
// onto its direction now (the shortest rotation between the two), so tilting the instrument
// swings the held tissue round the tip. The shaft's roll is not part of the pose, so turning the
// tool about its own axis does not. Opening the jaws releases them.
//
// The springs are penalty contacts (PenaltyContacts.h), so the integrators carry them as they
// carry the instrument's contacts: in the implicit step's Newton matrix (the spring can be stiff
// and holds the tissue's weight without lag), as impulses in the explicit one. Each spring is
// three pairs of opposed one-sided contacts on the node, one pair per axis e:
//   delta_+ = e . x_i - e . t_i,   delta_- = -delta_+
// whichever is positive pushes the node back with k |delta| along -+e, which together is
// exactly k (t_i - x_i). They pull as well as push, so they are tethers: their force counts in
// what the tool feels, their stretch not as penetration.

#include <vector>

#include "forces/ContactProvider.h"
#include "forces/PenaltyContacts.h"

namespace tissuesim {

class Grasp {
 public:
  /// @param reach_m nodes within this distance of the tip are caught when the jaws close.
  /// @param stiffness_N_m k, per node; damping_N_s_m the explicit integrator's contact damping.
  /// k's default (N/m), stiff against an organ's surface node.
  static constexpr double kDefaultStiffness_N_m = 2000.0;

  Grasp(std::vector<int> candidateNodes, double reach_m,
        double stiffness_N_m = kDefaultStiffness_N_m, double damping_N_s_m = 0.5)
      : m_candidates(std::move(candidateNodes)),
        m_reach_m(reach_m),
        m_stiffness(stiffness_N_m),
        m_damping(damping_N_s_m) {}

  /// Captures on closing, releases on opening, and adds the holding springs to `contacts`.
  void apply(const Eigen::Matrix3Xd& x, const InstrumentPose& pose, PenaltyContactSet& contacts);

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
