#pragma once
// The engine's view of collision: given node positions and the instrument's pose, add contact
// forces to the nodes and return the reaction on the instrument. collision/ implements it with
// FCL; the engine runs and tests without it (no provider: no contact).

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace tissuesim {

/// The rigid probe: a capsule of radius r whose axis runs from the tip back along `direction`
/// for `length_m` (the shaft). Metres.
struct InstrumentPose {
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  ///< unit, pointing from shaft to tip
  bool isGrasping = false;  ///< the grasper's jaws closed: hold the surface nodes at the tip
};

struct ContactResult {
  Eigen::Vector3d toolForce_N = Eigen::Vector3d::Zero();    ///< on the instrument
  Eigen::Vector3d toolTorque_Nm = Eigen::Vector3d::Zero();  ///< on the instrument, about the tip
  double maxPenetration_m = 0.0;
  int contactNodes = 0;  ///< contact points (triangles or nodes) pushing
};

class ContactProvider {
 public:
  virtual ~ContactProvider() = default;
  /// forces (3 by #V, N) += contact forces at positions x (3 by #V, m), velocities v (m/s).
  virtual ContactResult addContactForces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                                         const InstrumentPose& pose, Eigen::Matrix3Xd& forces) = 0;
};

}  // namespace tissuesim
