// SPDX-License-Identifier: Apache-2.0
// The tray as a support: what it carries and how far the tissue sinks into it.
#include "sim/TraySupport.h"

#include <cmath>

#include <gtest/gtest.h>

#include "forces/PlaneFriction.h"
#include "integrators/ImplicitEulerSolver.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kGravity_m_s2 = 9.81;

/// A block of liver (4 x 4 x 2 cm) let fall 1 mm onto a tray and settle there with damping: no
/// node is fixed, so the tray alone carries it.
struct BlockOnTray {
  Eigen::Vector3d size_m{0.04, 0.04, 0.02};
  Eigen::Vector3i cells{4, 4, 2};
  test::BlockSystem block{size_m, cells, SpringLaw::Eesm, false, 1e5};
  SceneGeometry geometry;
  SceneTray tray;
  std::unique_ptr<TraySupport> support;
  MechanicalState state;

  explicit BlockOnTray(double stiffness_Pa_per_m = 3e7) {
    geometry.mesh = makeBlockMesh(size_m, cells);
    tray.up = Eigen::Vector3d::UnitZ();
    tray.height_m = -0.001;
    tray.stiffness_Pa_per_m = stiffness_Pa_per_m;
    support = std::make_unique<TraySupport>(geometry, tray);
    block.system.gravity.acceleration_m_s2 = {0.0, 0.0, -kGravity_m_s2};
    block.system.contacts.reserve(static_cast<std::size_t>(support->pointCount()));
    state = block.system.restState();
    IntegratorSettings settings;
    settings.massDamping_1_s = 40.0;
    settings.maxIterations = 4;
    ImplicitEulerSolver solver(settings, LinearSolverKind::ConjugateGradient);
    for (int n = 0; n < 400; ++n) {
      block.system.contacts.clear();
      support->findContacts(state.x, block.system.contacts);
      const StepReport report = solver.step(block.system, state, 0.005);
      EXPECT_TRUE(report.isFinite && !report.refused) << n;
    }
  }
  double weight_N() const { return block.mesh.nodeMass_kg.sum() * kGravity_m_s2; }
};

TEST(TraySupport, CarriesTheWholeWeightOfWhatRestsOnIt) {
  const BlockOnTray t;
  EXPECT_LT(t.state.v.colwise().norm().maxCoeff(), 1e-4);  // at rest
  const Eigen::Vector3d carried = t.support->force_N(t.state.x);
  EXPECT_NEAR(carried.z(), t.weight_N(), 0.01 * t.weight_N());
  EXPECT_NEAR(carried.head<2>().norm(), 0.0, 1e-12);
  // Nothing pushes sideways on a frictionless tray: the block's centre of mass has not slid.
  const Eigen::VectorXd& mass = t.block.mesh.nodeMass_kg;
  const Eigen::Vector3d centre = t.state.x * mass / mass.sum();
  const Eigen::Vector3d centreAtRest = t.block.mesh.restPositions_m * mass / mass.sum();
  EXPECT_NEAR(centre.x(), centreAtRest.x(), 1e-9);
  EXPECT_NEAR(centre.y(), centreAtRest.y(), 1e-9);
}

TEST(TraySupport, TheTissueSinksAsThePenaltyPerUnitAreaSays) {
  // The block's weight over its footprint is a pressure p; a penalty of s per metre sinks it
  // p / s where only the footprint carries it, and somewhat less since the bottom rim's points
  // also carry their share of the sides' area.
  const BlockOnTray t;
  const double footprint_m2 = t.size_m.x() * t.size_m.y();
  const double sinkIfOnlyTheFootprint_m = t.weight_N() / footprint_m2 / t.tray.stiffness_Pa_per_m;
  const double sink_m = t.support->maxPenetration_m(t.state.x);
  EXPECT_LE(sink_m, 1.05 * sinkIfOnlyTheFootprint_m);
  EXPECT_GE(sink_m, 0.5 * sinkIfOnlyTheFootprint_m);
  // A tray four times as stiff: the block sinks a quarter as far.
  const BlockOnTray stiffer(4.0 * t.tray.stiffness_Pa_per_m);
  EXPECT_NEAR(stiffer.support->maxPenetration_m(stiffer.state.x), 0.25 * sink_m, 0.03 * sink_m);
}

TEST(TraySupport, OnlyPointsNearTheTrayBecomeContacts) {
  BlockOnTray t;
  PenaltyContactSet contacts;
  t.support->findContacts(t.block.system.restState().x, contacts);
  // At rest the bottom face lies 1 mm above the tray, within the detection margin; nothing else
  // does (the next layer is 1 cm up).
  const Eigen::Index bottomNodes = (t.cells.x() + 1) * (t.cells.y() + 1);
  EXPECT_EQ(static_cast<Eigen::Index>(contacts.contacts().size()), bottomNodes);
  for (const PenaltyContact& c : contacts.contacts()) {
    EXPECT_TRUE(c.isSupport);
    EXPECT_LT(c.penetration(t.block.system.restState().x), 0.0);  // not yet touching
  }
  const Eigen::Matrix3Xd raised =
      t.block.system.restState().x.colwise() + Eigen::Vector3d(0.0, 0.0, 0.01);
  contacts.clear();
  t.support->findContacts(raised, contacts);
  EXPECT_TRUE(contacts.empty());
}

/// The same block settled on a tray with friction mu, then the tray tipped theta (gravity
/// turned by theta about y, with the given mass damping): the block's centre of mass over the
/// next 0.5 s.
struct BlockOnInclinedTray {
  static constexpr double kTilt_rad = 20.0 * 3.14159265358979323846 / 180.0;  // tan 0.364
  test::BlockSystem block{{0.04, 0.04, 0.02}, {4, 4, 2}, SpringLaw::Eesm, false, 1e5};
  SceneGeometry geometry;
  std::unique_ptr<TraySupport> support;
  std::unique_ptr<PlaneFriction> friction;
  std::vector<double> centreX_m;  ///< every 0.1 s after the tilt
  double slidingTiesAtTheEnd = 0.0;

  explicit BlockOnInclinedTray(double coefficient, double damping_1_s = 0.0) {
    geometry.mesh = makeBlockMesh({0.04, 0.04, 0.02}, {4, 4, 2});
    SceneTray tray;
    tray.up = Eigen::Vector3d::UnitZ();
    tray.height_m = -0.001;
    tray.stiffness_Pa_per_m = 3e7;
    support = std::make_unique<TraySupport>(geometry, tray);
    friction = std::make_unique<PlaneFriction>(support->points(), tray.up, tray.height_m,
                                               coefficient, block.mesh.nodeCount());
    block.system.addField(*friction);
    block.system.contacts.reserve(static_cast<std::size_t>(support->pointCount()));
    MechanicalState state = block.system.restState();
    const Eigen::VectorXd& mass = block.mesh.nodeMass_kg;
    const auto step = [&](ImplicitEulerSolver& solver, double h) {
      block.system.contacts.clear();
      support->findContacts(state.x, block.system.contacts);
      friction->beginStep(state.x);
      const StepReport report = solver.step(block.system, state, h);
      EXPECT_TRUE(report.isFinite && !report.refused);
      friction->acceptStep(state.x);
    };
    IntegratorSettings settling;
    settling.massDamping_1_s = 40.0;
    settling.maxIterations = 4;
    ImplicitEulerSolver settler(settling, LinearSolverKind::ConjugateGradient);
    block.system.gravity.acceleration_m_s2 = {0.0, 0.0, -kGravity_m_s2};
    for (int n = 0; n < 400; ++n) step(settler, 0.005);
    IntegratorSettings free;
    free.massDamping_1_s = damping_1_s;
    free.maxIterations = 8;
    free.forceTolerance_N = 1e-9;
    free.linearTolerance = 1e-8;
    ImplicitEulerSolver solver(free, LinearSolverKind::ConjugateGradient);
    block.system.gravity.acceleration_m_s2 =
        kGravity_m_s2 * Eigen::Vector3d(std::sin(kTilt_rad), 0.0, -std::cos(kTilt_rad));
    for (int n = 0; n <= 500; ++n) {
      if (n % 100 == 0) centreX_m.push_back((state.x.row(0) * mass)(0) / mass.sum());
      if (n < 500) step(solver, 0.001);
    }
    slidingTiesAtTheEnd = friction->slidingCount(state.x);
  }
  /// The centre's acceleration along the slope from its last three samples (m/s^2).
  double acceleration_m_s2() const {
    return (centreX_m[5] - 2.0 * centreX_m[4] + centreX_m[3]) / (0.1 * 0.1);
  }
};

TEST(TraySupport, WithFrictionABlockSlidesDownASteepTrayAsCoulombSays) {
  // On a slope of 20 degrees a block slides with g (sin theta - mu cos theta) when mu is below
  // tan theta = 0.364: frictionless, and at mu 0.2.
  for (const double mu : {0.0, 0.2}) {
    const BlockOnInclinedTray t(mu);
    const double theta = BlockOnInclinedTray::kTilt_rad;
    const double expected = kGravity_m_s2 * (std::sin(theta) - mu * std::cos(theta));
    EXPECT_NEAR(t.acceleration_m_s2(), expected, 0.03 * expected) << "mu " << mu;
    if (mu > 0.0) {
      EXPECT_GT(t.slidingTiesAtTheEnd, 0) << "it slides";
    }
  }
}

TEST(TraySupport, WithFrictionABlockHoldsOnASlopeBelowItsAngleOfRepose) {
  // mu 0.6 > tan 20 degrees: the block leans over by the tissue's shear (about a millimetre for
  // this soft a tissue), then stays, where a block that cannot slip at all (mu 3) stays too; at
  // mu 0.2 it would be 19 cm down the slope by then.
  const BlockOnInclinedTray held(0.6, 20.0);
  const BlockOnInclinedTray stuck(3.0, 20.0);
  const double leaned_m = held.centreX_m[5] - held.centreX_m[0];
  EXPECT_GT(leaned_m, 0.0);
  EXPECT_LT(leaned_m, 2e-3);
  EXPECT_NEAR(leaned_m, stuck.centreX_m[5] - stuck.centreX_m[0], 5e-4);
  EXPECT_LT(std::abs(held.centreX_m[5] - held.centreX_m[4]), 5e-6);  // no creep
  EXPECT_EQ(held.slidingTiesAtTheEnd, 0);
}

}  // namespace
}  // namespace tissuesim
