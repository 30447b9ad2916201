// SPDX-License-Identifier: Apache-2.0
// A point's gap to a capsule: its normal is the gap's gradient and capsuleGapCurvature its
// Hessian, checked by central differences beside the shaft, at the round tip and at the top's end.

#include "forces/CapsuleGap.h"

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

constexpr double kProbeRadius_m = 0.0025;

/// The gap's Hessian by central differences of its normal (its gradient), step h (m).
Eigen::Matrix3d curvatureByDifferences(const Eigen::Vector3d& s, const Eigen::Vector3d& tip,
                                       const Eigen::Vector3d& top, double h) {
  Eigen::Matrix3d hessian;
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(c);
    hessian.col(c) = (capsuleGap(s + step, tip, top, kProbeRadius_m).normal -
                      capsuleGap(s - step, tip, top, kProbeRadius_m).normal) /
                     (2.0 * h);
  }
  return hessian;
}

TEST(CapsuleGap, TheNormalIsTheGapsGradientAndTheCurvatureItsHessian) {
  const Eigen::Vector3d tip(0.001, -0.002, 0.003);
  const Eigen::Vector3d top = tip + Eigen::Vector3d(0.02, 0.09, -0.03);
  const Eigen::Vector3d axis = (top - tip).normalized();
  Eigen::Vector3d across = axis.cross(Eigen::Vector3d::UnitX()).normalized();
  const struct {
    const char* where;
    Eigen::Vector3d s;
    bool isBesideShaft;
  } cases[] = {
      {"beside the shaft, pressed in", tip + 0.03 * axis + 0.0021 * across, true},
      {"beside the shaft, outside", tip + 0.05 * axis + 0.004 * across, true},
      {"at the round tip, pressed in", tip + 0.0015 * (-axis + 0.8 * across).normalized(), false},
      {"beyond the top's end", top + 0.002 * (axis + across).normalized(), false},
  };
  for (const auto& c : cases) {
    const CapsuleGap at = capsuleGap(c.s, tip, top, kProbeRadius_m);
    EXPECT_EQ(at.isBesideShaft, c.isBesideShaft) << c.where;
    EXPECT_NEAR(at.distance_m, at.gap_m + kProbeRadius_m, 1e-15) << c.where;
    // The gradient: the gap's central differences along each axis.
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d step = 1e-7 * Eigen::Vector3d::Unit(k);
      const double slope = (capsuleGap(c.s + step, tip, top, kProbeRadius_m).gap_m -
                            capsuleGap(c.s - step, tip, top, kProbeRadius_m).gap_m) /
                           2e-7;
      EXPECT_NEAR(slope, at.normal[k], 1e-6) << c.where;
    }
    const Eigen::Matrix3d curvature = capsuleGapCurvature(at, tip, top);
    const Eigen::Matrix3d expected = curvatureByDifferences(c.s, tip, top, 1e-7);
    EXPECT_LT((curvature - expected).cwiseAbs().maxCoeff(), 1e-5 * expected.norm()) << c.where;
    EXPECT_GT(curvature.norm(), 100.0) << c.where << ": the normal turns (1/m)";
  }
}

TEST(CapsuleGap, OnTheAxisTheCurvatureIsZero) {
  const Eigen::Vector3d tip(0.0, 0.0, 0.0), top(0.0, 0.0, 0.1);
  const CapsuleGap at = capsuleGap(Eigen::Vector3d(0.0, 0.0, 0.05), tip, top, kProbeRadius_m);
  EXPECT_EQ(at.distance_m, 0.0);
  EXPECT_EQ(capsuleGapCurvature(at, tip, top), Eigen::Matrix3d::Zero());
}

}  // namespace
}  // namespace tissuesim
