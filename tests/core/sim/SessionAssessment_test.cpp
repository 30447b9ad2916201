// SPDX-License-Identifier: Apache-2.0
#include "sim/SessionAssessment.h"

#include <gtest/gtest.h>

#include "mesh/BlockMesher.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kDt_s = 1e-3;

SpringMesh blockSprings() {
  return buildSpringMesh(makeBlockMesh({0.02, 0.01, 0.01}, {4, 2, 2}), 1000.0);
}

/// The rest positions stretched by `stretch` along x, y and z.
Eigen::Matrix3Xd stretched(const SpringMesh& mesh, const Eigen::Vector3d& stretch) {
  return stretch.asDiagonal() * mesh.restPositions_m;
}

TEST(SessionAssessment, AStretchBelowTheThresholdDamagesNothing) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  assessment.addStep(stretched(mesh, {1.15, 1.0, 1.0}), Eigen::Vector3d::Zero(), 0.0, kDt_s);
  const AssessmentSummary summary = assessment.summary();
  EXPECT_NEAR(summary.largestStretch, 1.15, 1e-12);  // the springs along x
  EXPECT_EQ(summary.damagedSpringCount, 0);
  EXPECT_EQ(summary.damagedVolume_m3, 0.0);
}

TEST(SessionAssessment, DamagedVolumeIsTheDamagedSpringsShareAndStaysAfterRelease) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  const Eigen::Matrix3Xd x = stretched(mesh, {1.25, 1.0, 1.0});
  EXPECT_NEAR(assessment.addStep(x, Eigen::Vector3d::Zero(), 0.0, kDt_s), 1.25, 1e-12);
  // Independently: each spring's share is a sixth of the tets whose edge it is; the damaged are
  // those stretched to 1.18 or more at x.
  double expectedVolume = 0.0;
  long expectedCount = 0;
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    const int a = mesh.springs(0, s), b = mesh.springs(1, s);
    if ((x.col(b) - x.col(a)).norm() / mesh.restLength_m[s] < 1.18) continue;
    ++expectedCount;
    for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
      const auto tet = mesh.tets.col(t);
      if ((tet.array() == a).any() && (tet.array() == b).any())
        expectedVolume += mesh.tetRestVolume_m3[t] / 6.0;
    }
  }
  ASSERT_GT(expectedCount, 0);
  ASSERT_LT(expectedCount, mesh.springCount());
  AssessmentSummary summary = assessment.summary();
  EXPECT_EQ(summary.damagedSpringCount, expectedCount);
  EXPECT_NEAR(summary.damagedVolume_m3, expectedVolume, 1e-15);
  EXPECT_GT(summary.damagedFraction(), 0.0);
  EXPECT_LT(summary.damagedFraction(), 1.0);

  // Back at rest: the damage is kept, the largest stretch too; the step's own is 1.
  EXPECT_NEAR(assessment.addStep(mesh.restPositions_m, Eigen::Vector3d::Zero(), 0.0, kDt_s), 1.0,
              1e-12);
  summary = assessment.summary();
  EXPECT_EQ(summary.damagedSpringCount, expectedCount);
  EXPECT_NEAR(summary.largestStretch, 1.25, 1e-12);
  Eigen::VectorXd nodeDamage;
  damagedNodes(mesh, assessment.damagedSprings(), nodeDamage);
  EXPECT_GT(nodeDamage.sum(), 0.0);
}

TEST(SessionAssessment, EverySpringDamagedIsTheWholeOrgan) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  assessment.addStep(stretched(mesh, {1.3, 1.3, 1.3}), Eigen::Vector3d::Zero(), 0.0, kDt_s);
  const AssessmentSummary summary = assessment.summary();
  EXPECT_EQ(summary.damagedSpringCount, mesh.springCount());
  EXPECT_NEAR(summary.organVolume_m3, 0.02 * 0.01 * 0.01, 1e-15);
  EXPECT_NEAR(summary.damagedFraction(), 1.0, 1e-12);
}

TEST(SessionAssessment, ToolFiguresFollowThePathAndTheForce) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  // From 2 mm before the origin: 10 steps without contact moving 1 mm a step along x, 10 at 5 N,
  // 5 at 10 N standing still.
  assessment.restart(Eigen::Vector3d(-2e-3, 0, 0));
  for (int n = 0; n < 10; ++n)
    assessment.addStep(mesh.restPositions_m, Eigen::Vector3d(1e-3 * n, 0, 0), 0.0, kDt_s);
  for (int n = 0; n < 10; ++n)
    assessment.addStep(mesh.restPositions_m, Eigen::Vector3d(9e-3, 0, 0), 5.0, kDt_s);
  for (int n = 0; n < 5; ++n)
    assessment.addStep(mesh.restPositions_m, Eigen::Vector3d(9e-3, 0, 0), 10.0, kDt_s);
  const AssessmentSummary summary = assessment.summary();
  EXPECT_NEAR(summary.duration_s, 25 * kDt_s, 1e-12);
  EXPECT_NEAR(summary.toolPathLength_m, 11e-3, 1e-12);
  EXPECT_EQ(summary.peakToolForce_N, 10.0);
  EXPECT_NEAR(summary.contactTime_s, 15 * kDt_s, 1e-12);
  EXPECT_NEAR(summary.meanContactForce_N, (10 * 5.0 + 5 * 10.0) / 15.0, 1e-12);
  EXPECT_NEAR(summary.aboveForceThreshold_s, 5 * kDt_s, 1e-12);
}

TEST(SessionAssessment, RestartClearsEverything) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  assessment.addStep(stretched(mesh, {1.3, 1.0, 1.0}), Eigen::Vector3d::Zero(), 9.0, kDt_s);
  assessment.addStep(mesh.restPositions_m, Eigen::Vector3d(0.01, 0, 0), 9.0, kDt_s);
  assessment.restart(Eigen::Vector3d::Zero());
  const AssessmentSummary summary = assessment.summary();
  EXPECT_EQ(summary.duration_s, 0.0);
  EXPECT_EQ(summary.toolPathLength_m, 0.0);
  EXPECT_EQ(summary.peakToolForce_N, 0.0);
  EXPECT_EQ(summary.aboveForceThreshold_s, 0.0);
  EXPECT_EQ(summary.largestStretch, 1.0);
  EXPECT_EQ(summary.damagedSpringCount, 0);
  EXPECT_EQ(summary.damagedVolume_m3, 0.0);
  for (const std::uint8_t isDamaged : assessment.damagedSprings()) EXPECT_EQ(isDamaged, 0);
}

TEST(SessionAssessment, ANewDamageStretchJudgesTheLargestStretchesAgain) {
  const SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  assessment.addStep(stretched(mesh, {1.2, 1.0, 1.0}), Eigen::Vector3d::Zero(), 0.0, kDt_s);
  assessment.addStep(mesh.restPositions_m, Eigen::Vector3d::Zero(), 0.0, kDt_s);
  const long damagedAt118 = assessment.summary().damagedSpringCount;
  ASSERT_GT(damagedAt118, 0);
  assessment.setDamageStretch(1.25);
  EXPECT_EQ(assessment.summary().damagedSpringCount, 0);
  EXPECT_EQ(assessment.summary().damagedVolume_m3, 0.0);
  assessment.setDamageStretch(1.18);
  EXPECT_EQ(assessment.summary().damagedSpringCount, damagedAt118);
  EXPECT_THROW(assessment.setDamageStretch(1.0), std::invalid_argument);
  EXPECT_EQ(assessment.summary().thresholds.damageStretch, 1.18);
}

TEST(SessionAssessment, RefusesThresholdsOutOfRange) {
  const SpringMesh mesh = blockSprings();
  EXPECT_THROW(SessionAssessment(mesh, {0.0, 1.18}), std::invalid_argument);
  EXPECT_THROW(SessionAssessment(mesh, {8.0, 0.9}), std::invalid_argument);
  EXPECT_THROW(SessionAssessment(mesh, {8.0, std::nan("")}), std::invalid_argument);
}

TEST(SessionAssessment, OneThreadAndTwoGiveTheSameFigures) {
  const SpringMesh mesh = blockSprings();
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.restPositions_m, 7, 1e-3);
  SessionAssessment alone(mesh, {8.0, 1.12});
  SessionAssessment pooled(mesh, {8.0, 1.12});
  ForkJoinPool pool(2);
  pooled.setThreadPool(&pool);
  for (SessionAssessment* assessment : {&alone, &pooled})
    assessment->addStep(deformed.x, Eigen::Vector3d::Zero(), 1.0, kDt_s);
  EXPECT_GT(alone.summary().damagedSpringCount, 0);
  EXPECT_EQ(alone.summary().damagedVolume_m3, pooled.summary().damagedVolume_m3);
  EXPECT_EQ(alone.summary().largestStretch, pooled.summary().largestStretch);
  EXPECT_EQ(alone.damagedSprings(), pooled.damagedSprings());
}

TEST(SessionAssessment, AMeshTakenUpKeepsTheDamageWhereItWasDone) {
  // The block's springs stretched past the threshold in its left half only; the same block then
  // meshed twice as finely (the mesh rebuilt in place, as a body made again is).
  SpringMesh mesh = blockSprings();
  SessionAssessment assessment(mesh, {8.0, 1.18});
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (x(0, i) <= 0.01 + 1e-12) x(0, i) *= 1.3;  // the left half stretched 1.3 along x
  }
  assessment.addStep(x, Eigen::Vector3d(0.0, 0.0, 0.01), 2.0, kDt_s);
  const AssessmentSummary before = assessment.summary();
  ASSERT_GT(before.damagedSpringCount, 0);
  mesh = buildSpringMesh(makeBlockMesh({0.02, 0.01, 0.01}, {8, 4, 4}), 1000.0);
  assessment.takeUpMesh([&] {
    // The peaks as springPeaks() gave them before the mesh was rebuilt: from a copy.
    const SpringMesh coarse = blockSprings();
    SessionAssessment again(coarse, {8.0, 1.18});
    again.addStep(x, Eigen::Vector3d::Zero(), 0.0, kDt_s);
    return again.springPeaks();
  }());
  const AssessmentSummary after = assessment.summary();
  // The session's other figures go on.
  EXPECT_EQ(after.duration_s, before.duration_s);
  EXPECT_EQ(after.peakToolForce_N, before.peakToolForce_N);
  EXPECT_EQ(after.largestStretch, before.largestStretch);
  EXPECT_NEAR(after.organVolume_m3, before.organVolume_m3, 1e-15);
  // Damage on the new mesh lies in the left half and nowhere in the right.
  const std::vector<std::uint8_t>& damaged = assessment.damagedSprings();
  ASSERT_EQ(static_cast<Eigen::Index>(damaged.size()), mesh.springCount());
  long left = 0, right = 0;
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    if (damaged[static_cast<std::size_t>(s)] == 0) continue;
    const double middle = 0.5 * (mesh.restPositions_m(0, mesh.springs(0, s)) +
                                 mesh.restPositions_m(0, mesh.springs(1, s)));
    (middle < 0.01 ? left : right) += 1;
  }
  EXPECT_GT(left, before.damagedSpringCount);  // more, finer springs there
  EXPECT_EQ(right, 0);
  EXPECT_EQ(after.damagedSpringCount, left);
  EXPECT_GT(after.damagedVolume_m3, 0.0);
  EXPECT_LT(after.damagedVolume_m3, 0.5 * after.organVolume_m3 + 1e-15);
  // And it goes on judging the new mesh's springs.
  assessment.addStep(mesh.restPositions_m * 1.25, Eigen::Vector3d::Zero(), 0.0, kDt_s);
  EXPECT_EQ(assessment.summary().damagedSpringCount, mesh.springCount());
}

}  // namespace
}  // namespace tissuesim
