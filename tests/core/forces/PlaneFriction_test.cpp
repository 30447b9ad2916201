// SPDX-License-Identifier: Apache-2.0
// Coulomb friction on a plane: a tie holds like a spring up to mu N and slides with mu N beyond,
// its energy's derivatives are its forces and stiffness, and the anchors follow Coulomb's law
// between steps.
#include "forces/PlaneFriction.h"

#include <random>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "numerics/NodeBlockMatrix.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kStiffness_N_m = 100.0;
constexpr double kSink_m = 1e-3;
constexpr double kCoefficient = 0.5;
constexpr double kLimit_N = kCoefficient * kStiffness_N_m * kSink_m;  // mu N
constexpr double kReach_m = kLimit_N / kStiffness_N_m;                // 0.5 mm

/// A 2 x 2 x 2 cm block whose bottom nodes (z = 0) sink 1 mm into the plane z = 1 mm, each a
/// point of its own, anchored where it rests; then node i of the bottom moved (0.15 + 0.1 i) mm
/// along x, and the tie's step begun at rest: the first four stick, the rest slide.
struct TiedBlock {
  test::BlockSystem block{{0.02, 0.02, 0.02}, {2, 2, 2}};
  std::vector<int> bottom;
  std::unique_ptr<PlaneFriction> friction;
  Eigen::Matrix3Xd rest;
  Eigen::Matrix3Xd x;

  TiedBlock() {
    rest = block.mesh.restPositions_m;
    std::vector<CarriedSurfacePoint> points;
    for (Eigen::Index node = 0; node < rest.cols(); ++node) {
      if (rest(2, node) != 0.0) continue;
      bottom.push_back(static_cast<int>(node));
      CarriedSurfacePoint point;
      point.nodes.fill(static_cast<int>(node));
      point.stiffness_N_m = kStiffness_N_m;
      points.push_back(point);
    }
    friction = std::make_unique<PlaneFriction>(points, Eigen::Vector3d::UnitZ(), kSink_m,
                                               kCoefficient, rest.cols());
    friction->acceptStep(rest);
    friction->beginStep(rest);
    x = rest;
    for (std::size_t i = 0; i < bottom.size(); ++i)
      x(0, bottom[i]) += 1e-4 * (1.5 + static_cast<double>(i));
  }
  Eigen::Matrix3Xd forces(const Eigen::Matrix3Xd& at, const ForcePass& pass = {}) const {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, at.cols());
    ForceReport report;
    friction->addForces(at, f, pass, report);
    return f;
  }
};

TEST(PlaneFriction, ATieHoldsLikeASpringUpToMuNAndSlidesWithMuNBeyond) {
  const TiedBlock t;
  ASSERT_EQ(t.bottom.size(), 9u);
  EXPECT_EQ(t.friction->tieCount(), 9);
  EXPECT_EQ(t.friction->slidingCount(t.x), 5);  // moved 0.55 mm and more: past the reach
  const Eigen::Matrix3Xd f = t.forces(t.x);
  for (std::size_t i = 0; i < t.bottom.size(); ++i) {
    const double moved_m = 1e-4 * (1.5 + static_cast<double>(i));
    const double expected_N = moved_m <= kReach_m ? kStiffness_N_m * moved_m : kLimit_N;
    EXPECT_NEAR(f(0, t.bottom[i]), -expected_N, 1e-12) << i;
    EXPECT_EQ(f(1, t.bottom[i]), 0.0);
    EXPECT_EQ(f(2, t.bottom[i]), 0.0);  // friction acts in the plane only
  }
  // Pressed further into the plane or lifted within the step, a tie keeps the limit it started
  // the step with (the normal force lagged one step).
  Eigen::Matrix3Xd pressed = t.x;
  pressed.row(2).array() -= 1e-3;
  EXPECT_LT((t.forces(pressed) - f).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PlaneFriction, ItsForcesAndStiffnessAreItsEnergysDerivatives) {
  const TiedBlock t;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Matrix3Xd direction(3, t.x.cols());
  for (Eigen::Index i = 0; i < direction.size(); ++i) direction.data()[i] = uniform(random);
  // Slanting slips (y as well as x), sliding and sticking, away from the branches' seam.
  Eigen::Matrix3Xd x = t.x;
  for (std::size_t i = 0; i < t.bottom.size(); ++i) x(1, t.bottom[i]) += 3e-5 * uniform(random);
  constexpr double h = 1e-8;
  const double slope =
      (t.friction->energy(x + h * direction) - t.friction->energy(x - h * direction)) / (2.0 * h);
  const double work = t.forces(x).cwiseProduct(direction).sum();
  ASSERT_GT(std::abs(work), 1e-4);
  EXPECT_NEAR(slope, -work, 1e-6 * std::abs(work));

  const Eigen::Matrix3Xd df =
      (t.forces(x + h * direction) - t.forces(x - h * direction)) / (2.0 * h);
  t.forces(x, {StiffnessSlot::Current, /*isProjected=*/false});
  NodeBlockMatrix k = t.block.system.makeMatrix();
  k.setZero();
  t.friction->addStiffness(k);
  const Eigen::VectorXd flat =
      Eigen::Map<const Eigen::VectorXd>(direction.data(), direction.size());
  const Eigen::VectorXd expected = -Eigen::Map<const Eigen::VectorXd>(df.data(), df.size());
  const Eigen::VectorXd kd = k.matrix() * flat;
  EXPECT_LT((kd - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
  // The product and the diagonal blocks read the same K.
  t.friction->prepareProducts({0, 2, 5, 9, t.x.cols()});  // four parts
  Eigen::VectorXd product = Eigen::VectorXd::Zero(flat.size());
  for (int part = 0; part < ForceField::kParts; ++part)
    t.friction->addStiffnessProduct(part, flat.data(), product.data());
  EXPECT_LT((product - kd).cwiseAbs().maxCoeff(), 1e-12 * kd.cwiseAbs().maxCoeff());
  for (const int node : t.bottom) {
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    t.friction->addDiagonalBlock(node, block);
    const Eigen::Matrix3d dense = k.matrix().block(3 * node, 3 * node, 3, 3);
    EXPECT_LT((block - dense).cwiseAbs().maxCoeff(), 1e-12);
    // PSD, nothing along the normal.
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(block).eigenvalues().minCoeff(),
              -1e-12);
    EXPECT_EQ(block.row(2).norm(), 0.0);
  }
}

TEST(PlaneFriction, AnchorsFollowCoulombsLawBetweenSteps) {
  TiedBlock t;
  Eigen::Matrix3Xd x = t.x;
  x(2, t.bottom[8]) += 2e-3;  // lifted off the plane (1 mm above it)
  t.friction->acceptStep(x);
  const std::vector<PlaneFriction::Anchor>& anchors = t.friction->anchors();
  for (std::size_t i = 0; i + 1 < t.bottom.size(); ++i) {
    const double moved_m = 1e-4 * (1.5 + static_cast<double>(i));
    const double anchorMoved_m = anchors[i].position_m.x() - t.rest(0, t.bottom[i]);
    // A sticking tie's anchor stays; a sliding one's is dragged to the reach behind the point.
    EXPECT_NEAR(anchorMoved_m, moved_m <= kReach_m ? 0.0 : moved_m - kReach_m, 1e-12) << i;
    EXPECT_NEAR(anchors[i].position_m.z(), kSink_m, 1e-15);  // on the plane
    EXPECT_NEAR(anchors[i].limit_N, kLimit_N, 1e-15);
  }
  EXPECT_EQ(anchors[8].limit_N, 0.0);  // free
  // The next step ties only the eight still on the plane; the lifted one, set down 2 mm further
  // along, is anchored where it touches.
  t.friction->beginStep(x);
  EXPECT_EQ(t.friction->tieCount(), 8);
  x(2, t.bottom[8]) -= 2e-3;
  x(0, t.bottom[8]) += 2e-3;
  t.friction->acceptStep(x);
  EXPECT_NEAR(t.friction->anchors()[8].position_m.x(), x(0, t.bottom[8]), 1e-12);
  EXPECT_GT(t.friction->anchors()[8].limit_N, 0.0);
  // Released: nothing tied.
  t.friction->releaseAnchors();
  t.friction->beginStep(x);
  EXPECT_EQ(t.friction->tieCount(), 0);
  EXPECT_TRUE(t.forces(x).isZero(0.0));
}

}  // namespace
}  // namespace tissuesim
