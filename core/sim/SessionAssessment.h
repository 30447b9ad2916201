// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a session tells the trainee and the instructor (docs/assessment.md): how long it lasted,
// how far the tool travelled, how hard it pushed and for how long past a force threshold, how far
// the tissue was stretched, and how much of it was stretched past its damage threshold.
//
// Damage rule, per spring: spring e is damaged once its stretch lambda_e = |x_b - x_a| / L0 has
// reached the damage stretch lambda_d in the session; it stays damaged after the tool leaves
// (stretching tears the liver's capsule and parenchyma for good). The damaged volume is
//
//   V_damaged = sum over damaged springs e of V_e,   V_e = sum over tets t around e of V_t / 6
//
// (m^3): each spring's share of the rest volume (SpringMesh's rule, before any stiffness scale),
// so that V_damaged is the whole organ's volume when every spring is damaged. A spring's axial
// stretch is at most the largest principal stretch of the deformation around it, so the rule
// reads damage late rather than early. lambda_d comes from the tissue file (damage_stretch) or
// the scene; its default and source are in material/TissueParameters.h.
//
// Each step is one pass over the springs (squared stretches against squared thresholds: no
// square root), in kParts fixed ranges on the pool when one is given; sums run in part order, so
// the figures are bit-identical for any thread count. No allocation after construction.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "parallel/ForkJoinPool.h"
#include "springs/SpringMesh.h"

namespace tissuesim {

struct AssessmentThresholds {
  double toolForce_N = 8.0;     ///< > 0 (the scene's assessment.force_threshold_n)
  double damageStretch = 1.18;  ///< > 1 (the tissue's damage_stretch, or the scene's)
};

struct AssessmentSummary {
  double duration_s = 0.0;        ///< simulated time since the session began
  double toolPathLength_m = 0.0;  ///< the tip's path (as simulated: the proxy's, not the cursor's)
  double peakToolForce_N = 0.0;   ///< the largest contact force on the tool
  double meanContactForce_N = 0.0;     ///< its mean over the time in contact (0 without contact)
  double contactTime_s = 0.0;          ///< time with a force on the tool
  double aboveForceThreshold_s = 0.0;  ///< time with the force above the threshold
  double largestStretch = 1.0;         ///< over all springs and steps
  long damagedSpringCount = 0;
  double damagedVolume_m3 = 0.0;
  double organVolume_m3 = 0.0;  ///< the rest volume, for the damaged fraction
  AssessmentThresholds thresholds;

  double damagedFraction() const {
    return organVolume_m3 > 0.0 ? damagedVolume_m3 / organVolume_m3 : 0.0;
  }
};

class SessionAssessment {
 public:
  static constexpr int kParts = 4;

  /// `mesh` must outlive this object (its topology and rest lengths; volumes come from its tets).
  /// @throws std::invalid_argument for thresholds out of range.
  SessionAssessment(const SpringMesh& mesh, const AssessmentThresholds& thresholds);

  /// Runs the spring pass on `pool` (which must outlive its use), or on the caller when null.
  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }

  /// One step of duration dt_s that ended at positions x (3 by #V, m) with the tool's tip at
  /// tip_m and a force of toolForce_N (N) on it. The path runs from the tip given to the last
  /// restart() (the origin before any). @returns the step's largest stretch (its springs' are
  /// measured here anyway).
  double addStep(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& tip_m, double toolForce_N,
                 double dt_s);
  /// A new session, with the tool's tip at toolTip_m (where its path starts): every figure and
  /// every spring's damage cleared.
  void restart(const Eigen::Vector3d& toolTip_m);
  /// A new damage stretch (a new tissue): each spring is judged again on its largest stretch so
  /// far. @throws std::invalid_argument unless damageStretch > 1 and finite.
  void setDamageStretch(double damageStretch);

  /// Each spring's middle at rest (3 by #S, m) and its largest squared stretch so far: what
  /// takeUpMesh carries over to another mesh of the same organ.
  struct SpringPeaks {
    Eigen::Matrix3Xd middles_m;
    Eigen::VectorXd peakStretchSquared;
  };
  SpringPeaks springPeaks() const;
  /// The mesh (the same object, rebuilt in place: the organ meshed otherwise) taken up: its
  /// springs' rest lengths and volumes, each spring's largest stretch so far that of the spring
  /// in `peaks` whose middle is nearest its own, its damage judged again on it; the session's
  /// other figures (time, the tool's path and force, the largest stretch) go on. Allocates.
  void takeUpMesh(const SpringPeaks& peaks);

  AssessmentSummary summary() const;
  /// #S: 1 where the spring is damaged, else 0 (what the damage overlay draws).
  const std::vector<std::uint8_t>& damagedSprings() const { return m_isDamaged; }

 private:
  Eigen::Index partStart(int part) const { return m_mesh.springCount() * part / kParts; }
  /// Spring s's middle at rest (m).
  Eigen::Vector3d restMiddle(Eigen::Index s) const {
    return 0.5 * (m_mesh.restPositions_m.col(m_mesh.springs(0, s)) +
                  m_mesh.restPositions_m.col(m_mesh.springs(1, s)));
  }

  const SpringMesh& m_mesh;
  ForkJoinPool* m_pool = nullptr;
  AssessmentThresholds m_thresholds;
  Eigen::VectorXd m_inverseRestLengthSquared_1_m2;  ///< #S
  Eigen::VectorXd m_springVolume_m3;                ///< #S, V_e unscaled
  Eigen::VectorXd m_peakStretchSquared;             ///< #S, the largest lambda^2 so far
  std::vector<std::uint8_t> m_isDamaged;            ///< #S
  double m_organVolume_m3 = 0.0;

  double m_duration_s = 0.0;
  double m_pathLength_m = 0.0;
  double m_peakForce_N = 0.0;
  double m_contactImpulse_Ns = 0.0;  ///< integral of |F| dt over the time in contact
  double m_contactTime_s = 0.0;
  double m_aboveThreshold_s = 0.0;
  double m_largestStretchSquared = 1.0;
  long m_damagedCount = 0;
  double m_damagedVolume_m3 = 0.0;
  Eigen::Vector3d m_lastTip_m = Eigen::Vector3d::Zero();
};

/// Per node (damage: #V, overwritten): 1 where any spring of `mesh` at the node is damaged in
/// `damagedSprings` (#S, SessionAssessment::damagedSprings()), else 0.
void damagedNodes(const SpringMesh& mesh, const std::vector<std::uint8_t>& damagedSprings,
                  Eigen::VectorXd& damage);

}  // namespace tissuesim
