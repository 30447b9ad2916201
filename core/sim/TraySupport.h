// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tray under the organ as a support: the tissue's surface points may not pass below the
// plane up . y = h. Each point that is near the plane at a step's start becomes a penalty
// contact for that step (PenaltyContacts.h), with the instrument's, inside the implicit solve:
//
//   delta = h - up . y_p          penetration of surface point p (m), pushed when > 0
//   f = k_p delta up,  k_p = s A_p     (N; s the scene's stiffness_Pa_per_m, A_p the point's
//                                        share of the surface area at rest, m^2)
//
// A penalty per unit area, so the support's pressure under a given sag (s delta, Pa) does not
// depend on how finely the surface is meshed. The points are the drawn surface's vertices when
// the scene has one (each carried by the tet that holds it at rest, through its barycentric
// weights clamped to that tet, the gap to the drawn point frozen into the step's offset, as
// the instrument's contact on the drawn surface does), else the tet mesh's boundary nodes.
// Friction, when the scene asks for it (tray.friction, Coulomb's mu), is a force field of its
// own over the same points (forces/PlaneFriction.h), which frictionless scenes leave out.

#include <vector>

#include <Eigen/Core>

#include "forces/PenaltyContacts.h"
#include "forces/PlaneFriction.h"
#include "sim/SceneFile.h"
#include "sim/SceneGeometry.h"

namespace tissuesim {

class TraySupport {
 public:
  /// Points within this height above the tray at a step's start get a contact for the step:
  /// more than a surface point moves in one step (2 m/s at 1 ms).
  static constexpr double kDetectionMargin_m = 0.002;

  TraySupport(const SceneGeometry& geometry, const SceneTray& tray);

  /// Adds the contacts of the points within kDetectionMargin_m of the tray (or below it) at x
  /// (3 by #V tet-node positions, m). No allocation once `contacts` has room for pointCount().
  void findContacts(const Eigen::Matrix3Xd& x, PenaltyContactSet& contacts) const;

  Eigen::Index pointCount() const { return static_cast<Eigen::Index>(m_points.size()); }
  /// The deepest penetration of any point below the tray at x (m; 0 when none is below).
  double maxPenetration_m(const Eigen::Matrix3Xd& x) const;
  /// The support's normal force on the tissue at x (N): what the tray carries.
  Eigen::Vector3d force_N(const Eigen::Matrix3Xd& x) const;

  /// The points that can touch the tray, each with its normal penalty.
  const std::vector<CarriedSurfacePoint>& points() const { return m_points; }
  const Eigen::Vector3d& up() const { return m_up; }
  double height_m() const { return m_height_m; }

 private:
  std::vector<CarriedSurfacePoint> m_points;
  Eigen::Vector3d m_up;
  double m_height_m;
};

}  // namespace tissuesim
