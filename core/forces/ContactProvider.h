// SPDX-License-Identifier: Apache-2.0
#pragma once
// The engine's view of collision: given node positions and the instrument's pose, find where
// the instrument touches (or is about to touch) the tissue, as penalty contacts frozen for the
// coming step (PenaltyContacts.h); the integrator evaluates them at its trial states.
// collision/ implements it with FCL; the engine runs and tests without it (no provider: no
// contact).

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include "forces/PenaltyContacts.h"

namespace tissuesim {

/// The rigid probe: a capsule of radius r whose axis runs from the tip back along `direction`
/// for `length_m` (the shaft). Metres.
struct InstrumentPose {
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  ///< unit, pointing from shaft to tip
  bool isGrasping = false;  ///< the grasper's jaws closed: hold the surface nodes at the tip
};

class ContactProvider {
 public:
  virtual ~ContactProvider() = default;
  /// Adds to `contacts` the contacts between the tissue at positions x (3 by #V, m) and the
  /// instrument at `pose` (the pose at the end of the coming step).
  virtual void findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                            PenaltyContactSet& contacts) = 0;
};

}  // namespace tissuesim
