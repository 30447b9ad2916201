// SPDX-License-Identifier: Apache-2.0
// Tests of the three time integrators on small systems: analytic trajectories, stability at
// the extremes, energy behaviour, refusal and rollback.

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "integrators/ImplicitEulerSolver.h"
#include "integrators/QuasiNewtonSolver.h"
#include "integrators/SymplecticEulerSolver.h"
#include "parallel/ForkJoinPool.h"
#include "parallel/NodeRanges.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

std::unique_ptr<TimeIntegrator> makeIntegrator(const std::string& name,
                                               IntegratorSettings settings) {
  if (name == "explicit") return std::make_unique<SymplecticEulerSolver>(settings);
  if (name == "implicit")
    return std::make_unique<ImplicitEulerSolver>(settings, LinearSolverKind::Cholesky);
  if (name == "implicit-cg")
    return std::make_unique<ImplicitEulerSolver>(settings, LinearSolverKind::ConjugateGradient);
  return std::make_unique<QuasiNewtonSolver>(settings);
}

Eigen::Vector3d centreOfMass(const SpringMesh& mesh, const Eigen::Matrix3Xd& x) {
  return x * mesh.nodeMass_kg / mesh.nodeMass_kg.sum();
}

class EachIntegrator : public ::testing::TestWithParam<std::string> {};

TEST_P(EachIntegrator, FreeFallFollowsTheDiscreteAndAnalyticTrajectory) {
  test::BlockSystem block({0.01, 0.01, 0.01}, {1, 1, 1});
  block.system.gravity.acceleration_m_s2 = kGravity;
  IntegratorSettings settings;
  settings.forceTolerance_N = 1e-12;
  auto integrator = makeIntegrator(GetParam(), settings);
  MechanicalState state = block.system.restState();
  const Eigen::Vector3d start = centreOfMass(block.mesh, state.x);
  const double dt = 1e-3;
  const int steps = 200;
  for (int n = 0; n < steps; ++n) ASSERT_FALSE(integrator->step(block.system, state, dt).refused);
  const double t = steps * dt;
  const double drop = start.z() - centreOfMass(block.mesh, state.x).z();
  // Both Euler variants give z_n = -g dt^2 n (n + 1) / 2 exactly for a rigid fall ...
  EXPECT_NEAR(drop, 9.81 * dt * dt * steps * (steps + 1) / 2.0, 1e-9);
  // ... which is the analytic g t^2 / 2 to first order in dt.
  EXPECT_NEAR(drop, 9.81 * t * t / 2.0, 9.81 * dt * t / 2.0 + 1e-9);
  // A rigid fall does not deform.
  EXPECT_LT((state.x.colwise() - centreOfMass(block.mesh, state.x) -
             (block.mesh.restPositions_m.colwise() - start))
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
}

TEST_P(EachIntegrator, NonFiniteInputIsDetectedAndTheStateKept) {
  test::BlockSystem block({0.01, 0.01, 0.01}, {1, 1, 1});
  auto integrator = makeIntegrator(GetParam(), IntegratorSettings{});
  MechanicalState state = block.system.restState();
  state.x.row(0) *= 1.05;
  const MechanicalState good = state;
  block.system.externalForces_N(1, 3) = std::numeric_limits<double>::quiet_NaN();
  const StepReport report = integrator->step(block.system, state, 1e-3);
  EXPECT_FALSE(report.isFinite && report.converged && !report.refused);
  EXPECT_TRUE(state.isFinite());
  EXPECT_EQ(state.x, good.x);  // the caller still has the last good state
  EXPECT_EQ(state.v, good.v);
}

INSTANTIATE_TEST_SUITE_P(All, EachIntegrator,
                         ::testing::Values("explicit", "implicit", "implicit-cg", "quasi-newton"),
                         [](const auto& integratorName) {
                           std::string name = integratorName.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

TEST(SymplecticEuler, OscillationPeriodMatchesTheLinearisedSystem) {
  // One tet, three nodes fixed; the free node oscillates with omega^2 = eig(K_33) / m_3.
  TetMesh tet;
  tet.nodes_m.resize(3, 4);
  tet.nodes_m << 0, 0.01, 0, 0, 0, 0, 0.01, 0, 0, 0, 0, 0.01;
  tet.tets.resize(4, 1);
  tet.tets << 0, 1, 2, 3;
  const auto& liver = test::LiverMaterial::instance();
  const SpringMesh mesh = buildSpringMesh(tet, 1060.0);
  const SpringForceLaw law(SpringLaw::Smm, liver.table, liver.parameters, 5000.0, false);
  SpringForceField springs(mesh, law);
  MechanicalSystem system(springs, nullptr);
  for (int node = 0; node < 3; ++node) system.fixNode(node);
  Eigen::Matrix3d k33 = Eigen::Matrix3d::Zero();
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    if (mesh.springs(1, s) != 3) continue;
    const Eigen::Vector3d n =
        (mesh.restPositions_m.col(3) - mesh.restPositions_m.col(mesh.springs(0, s))).normalized();
    k33 += mesh.volume_m3[s] * 5000.0 / (mesh.restLength_m[s] * mesh.restLength_m[s]) * n *
           n.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> modes(k33);
  const double omega = std::sqrt(modes.eigenvalues()[0] / mesh.nodeMass_kg[3]);
  MechanicalState state = system.restState();
  state.x.col(3) += 1e-7 * modes.eigenvectors().col(0);
  IntegratorSettings settings;
  SymplecticEulerSolver integrator(settings);
  const double period = 2 * M_PI / omega;
  const double dt = period / 2000;
  double previous = modes.eigenvectors().col(0).dot(state.x.col(3) - mesh.restPositions_m.col(3));
  std::vector<double> crossings;
  for (int n = 1; n < 2000 * 5; ++n) {
    integrator.step(system, state, dt);
    const double now =
        modes.eigenvectors().col(0).dot(state.x.col(3) - mesh.restPositions_m.col(3));
    if (previous > 0 && now <= 0) crossings.push_back(n * dt - dt * now / (now - previous));
    previous = now;
  }
  ASSERT_GE(crossings.size(), 3u);
  const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(measured, period, 2e-3 * period);
}

TEST(SymplecticEuler, HundredThousandStepsStayFiniteWithBoundedEnergy) {
  test::BlockSystem block({0.01, 0.01, 0.01}, {1, 1, 1});
  block.system.gravity.acceleration_m_s2 = kGravity;
  IntegratorSettings settings;
  SymplecticEulerSolver integrator(settings);
  MechanicalState state = block.system.restState();
  state.x.row(0) *= 1.1;  // released from a stretch: it vibrates while it falls
  // omega_max dt <= 0.4: symplectic Euler then holds a shadow energy within a few per cent of
  // the true one (its fluctuation is O((omega dt)^2)), with no drift.
  const double dt = 0.2 * SymplecticEulerSolver::stableTimeStep(block.system, state.x, 1.0);
  // Energy in the falling frame: kinetic about the centre of mass plus elastic.
  const auto internalEnergy = [&](const MechanicalState& s) {
    MechanicalState relative = s;
    const Eigen::Vector3d vcm = s.v * block.mesh.nodeMass_kg / block.mesh.nodeMass_kg.sum();
    relative.v = s.v.colwise() - vcm;
    MechanicalSystem& system = block.system;
    const Eigen::Vector3d g = system.gravity.acceleration_m_s2;
    system.gravity.acceleration_m_s2.setZero();
    const double energy = system.totalEnergy(relative);
    system.gravity.acceleration_m_s2 = g;
    return energy;
  };
  const double initial = internalEnergy(state);
  ASSERT_GT(initial, 0.0);
  // Bounded: never far from the start. No drift: the first and last tenths average the same.
  double worst = 0.0;
  double firstTenth = 0.0;
  double lastTenth = 0.0;
  constexpr int kSteps = 100000;
  constexpr int kSampleEvery = 100;
  for (int n = 0; n < kSteps; ++n) {
    const StepReport report = integrator.step(block.system, state, dt);
    ASSERT_TRUE(report.isFinite) << "step " << n;
    ASSERT_EQ(report.substeps, 1);
    if (n % kSampleEvery != 0) continue;
    const double energy = internalEnergy(state);
    worst = std::max(worst, std::abs(energy - initial));
    if (n < kSteps / 10) firstTenth += energy / (kSteps / 10 / kSampleEvery);
    if (n >= kSteps - kSteps / 10) lastTenth += energy / (kSteps / 10 / kSampleEvery);
  }
  EXPECT_LT(worst, 0.15 * initial);
  EXPECT_NEAR(lastTenth, firstTenth, 0.03 * initial);
  const double t = kSteps * dt;
  EXPECT_NEAR(-centreOfMass(block.mesh, state.x).z() + 0.005, 9.81 * t * t / 2, 9.81 * dt * t);
}

// The bound is taken at the nodes' largest K_i / m_i alone (h_max falls as omega^2 grows):
// it must be the smallest of every node's own h_max, with the damping in it.
TEST(SymplecticEuler, TheStableStepIsTheSmallestOfTheNodesBounds) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {3, 3, 3}, SpringLaw::Eesm, true);
  MechanicalState state = block.system.restState();
  for (Eigen::Index i = 0; i < state.x.cols(); ++i) {
    state.x.col(i) *= 1.0 + 0.1 * std::sin(7.0 * static_cast<double>(i));  // uneven stretches
  }
  IntegratorSettings settings;
  for (const double alpha : {0.0, 50.0, 5e4}) {
    settings.massDamping_1_s = alpha;
    block.springs.resetStretchHistory();  // each step commits its stretches
    Eigen::Matrix3Xd f(3, state.x.cols());
    Eigen::VectorXd nodeStiffness(state.x.cols());
    block.system.forcesAndNodeStiffness(state.x, f, nodeStiffness);
    double smallest = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < state.x.cols(); ++i) {
      const double omega2 = 2.0 * nodeStiffness[i] / block.mesh.nodeMass_kg[i];
      smallest = std::min(smallest, (std::sqrt(alpha * alpha + 4.0 * omega2) - alpha) / omega2);
    }
    SymplecticEulerSolver integrator(settings);
    MechanicalState copy = state;
    const StepReport report = integrator.step(block.system, copy, 1e-9);
    EXPECT_NEAR(report.stableTimeStep_s, settings.stabilitySafety * smallest, 1e-9 * smallest)
        << alpha;
  }
}

TEST(SymplecticEuler, RefusesAStepItCannotTakeStably) {
  test::BlockSystem block({0.01, 0.01, 0.01}, {1, 1, 1});
  IntegratorSettings settings;
  settings.maxSubsteps = 8;
  SymplecticEulerSolver integrator(settings);
  MechanicalState state = block.system.restState();
  state.x.row(0) *= 1.1;
  const MechanicalState before = state;
  const double stable =
      SymplecticEulerSolver::stableTimeStep(block.system, state.x, settings.stabilitySafety);
  const StepReport big = integrator.step(block.system, state, 100 * stable);
  EXPECT_TRUE(big.refused);
  EXPECT_FALSE(big.reason.empty());
  EXPECT_EQ(state.x, before.x);
  const StepReport fine = integrator.step(block.system, state, 4 * stable);
  EXPECT_FALSE(fine.refused);
  EXPECT_GE(fine.substeps, 2);  // fewer than 4: the bound is re-estimated as the block relaxes
  EXPECT_LE(fine.substeps, 8);
  EXPECT_NE(state.x, before.x);
}

TEST(ImplicitEuler, TenTimesTheExplicitStepNeitherBlowsUpNorGainsEnergy) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  MechanicalState state = block.system.restState();
  state.x.row(0) *= 1.2;
  const double dt = 10 * SymplecticEulerSolver::stableTimeStep(block.system, state.x, 1.0);
  IntegratorSettings settings;
  settings.forceTolerance_N = 1e-10;
  ImplicitEulerSolver integrator(settings, LinearSolverKind::Cholesky);
  double energy = block.system.totalEnergy(state);
  for (int n = 0; n < 300; ++n) {
    const StepReport report = integrator.step(block.system, state, dt);
    ASSERT_TRUE(report.isFinite);
    ASSERT_TRUE(report.converged) << "step " << n << " residual " << report.residual_N;
    const double now = block.system.totalEnergy(state);
    EXPECT_LE(now, energy * (1 + 1e-9) + 1e-15) << "step " << n;
    energy = now;
  }
}

// Newton takes each iteration's matrix from the previous line search's accepted trial; a
// matrix one iteration stale would still converge, but linearly. With the exact Hessian
// (Cholesky) the residual must fall quadratically: each iteration at least squares its ratio to
// the start, once the iterate is close.
TEST(ImplicitEuler, NewtonConvergesQuadraticallyWithTheExactHessian) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  for (int node = 0; node < 9; ++node) block.system.fixNode(node);  // the z = 0 face
  MechanicalState start = block.system.restState();
  start.x.row(0) *= 1.05;
  const double dt = 10 * SymplecticEulerSolver::stableTimeStep(block.system, start.x, 1.0);
  std::vector<double> residuals;
  for (int iterations = 0; iterations <= 8; ++iterations) {
    IntegratorSettings settings;
    settings.maxIterations = iterations;
    settings.forceTolerance_N = 0.0;
    MechanicalState state = start;
    residuals.push_back(ImplicitEulerSolver(settings, LinearSolverKind::Cholesky)
                            .step(block.system, state, dt)
                            .residual_N);
  }
  const double first = residuals[0];
  ASSERT_GT(first, 1e-3);
  int quadraticSteps = 0;
  for (std::size_t k = 1; k + 1 < residuals.size(); ++k) {
    const double ratio = residuals[k] / first;
    if (ratio > 1e-2 || residuals[k + 1] < 1e-12) continue;  // not yet close, or at round-off
    EXPECT_LT(residuals[k + 1] / first, 10.0 * ratio * ratio) << "iteration " << k + 1;
    ++quadraticSteps;
  }
  EXPECT_GE(quadraticSteps, 1) << "never close enough to see the rate";
  EXPECT_LT(residuals.back(), 1e-10);
}

TEST(QuasiNewton, ConvergesToImplicitEulerAsIterationsGrow) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  block.system.gravity.acceleration_m_s2 = kGravity;
  for (int node = 0; node < 9; ++node) block.system.fixNode(node);  // the z = 0 face
  MechanicalState start = block.system.restState();
  start.x.row(0) *= 1.15;
  const double dt = 10 * SymplecticEulerSolver::stableTimeStep(block.system, start.x, 1.0);
  IntegratorSettings exactSettings;
  exactSettings.forceTolerance_N = 1e-13;
  exactSettings.maxIterations = 50;
  MechanicalState exact = start;
  ImplicitEulerSolver(exactSettings, LinearSolverKind::Cholesky).step(block.system, exact, dt);
  double previousError = std::numeric_limits<double>::infinity();
  for (const int iterations : {1, 3, 10, 40}) {
    IntegratorSettings settings;
    settings.maxIterations = iterations;
    settings.forceTolerance_N = 0.0;
    MechanicalState state = start;
    QuasiNewtonSolver(settings).step(block.system, state, dt);
    const double error = (state.x - exact.x).cwiseAbs().maxCoeff();
    EXPECT_LT(error, previousError) << iterations << " iterations";
    previousError = error;
  }
  EXPECT_LT(previousError, 1e-9);
}

/// The block's nodes at height z (m), but the first `skipped`, as a support's contacts: a plane
/// at z = 0 under them, point p of the support being node p.
void addSupportContacts(MechanicalSystem& system, const SpringMesh& mesh, double z,
                        int skipped = 0) {
  for (Eigen::Index node = 0; node < mesh.nodeCount(); ++node) {
    if (std::abs(mesh.restPositions_m(2, node) - z) > 1e-9) continue;
    if (skipped-- > 0) continue;
    PenaltyContact contact;
    contact.nodes.fill(static_cast<int>(node));
    contact.weights = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
    contact.normal = -Eigen::Vector3d::UnitZ();  // out of the tissue, into the plane
    contact.stiffness_N_m = 2e3;
    contact.isSupport = true;
    contact.supportPoint = static_cast<int>(node);
    system.contacts.add(contact);
  }
}

TEST(QuasiNewton, ASupportThatDoesNotChangeIsFactorisedOnce) {
  // A block resting on a plane under gravity: the support's contacts are the same every step,
  // so H0, factorised with them at the first step, serves every step after.
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  block.system.gravity.acceleration_m_s2 = kGravity;
  addSupportContacts(block.system, block.mesh, 0.0);
  IntegratorSettings settings;
  settings.maxIterations = 20;
  settings.forceTolerance_N = 1e-12;
  QuasiNewtonSolver solver(settings);
  MechanicalState state = block.system.restState();
  for (int n = 0; n < 50; ++n) ASSERT_TRUE(solver.step(block.system, state, 1e-3).isFinite);
  EXPECT_EQ(solver.factorisationCount(), 1);
  // And it lands as implicit Euler lands it (falling through the plane, the block would be
  // 1.2 mm down after 50 ms).
  IntegratorSettings exactSettings;
  exactSettings.forceTolerance_N = 1e-12;
  exactSettings.maxIterations = 20;
  ImplicitEulerSolver exact(exactSettings, LinearSolverKind::Cholesky);
  MechanicalState reference = block.system.restState();
  for (int n = 0; n < 50; ++n) ASSERT_TRUE(exact.step(block.system, reference, 1e-3).isFinite);
  const double sunk_m = -reference.x.row(2).minCoeff();
  EXPECT_GT(sunk_m, 1e-6);
  EXPECT_LT(sunk_m, 1e-4);
  EXPECT_LT((state.x - reference.x).cwiseAbs().maxCoeff(), 0.02 * sunk_m);
}

TEST(QuasiNewton, SupportContactsTheFactorisationLacksOrHasInExcessAreExactWoodburyTerms) {
  // H0 factorised with the bottom layer's contacts; then the step's support is the bottom layer
  // with some points gone and the middle layer's added. The Woodbury terms (+ for what H0 lacks,
  // - for what it carries that the step has not) must give the step a solver factorised with
  // the step's own contacts takes. One iteration a step, no tolerance: the step is H^-1 applied
  // to the residual, so any error in H^-1 (a wrong sign) moves the result.
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  block.system.gravity.acceleration_m_s2 = kGravity;
  IntegratorSettings settings;
  settings.maxIterations = 1;
  settings.forceTolerance_N = 0.0;
  const auto stepWith = [&](QuasiNewtonSolver& solver, MechanicalState& state, int dropped,
                            bool withMiddle) {
    block.system.contacts.clear();
    addSupportContacts(block.system, block.mesh, 0.0, dropped);
    if (withMiddle) addSupportContacts(block.system, block.mesh, 0.01);
    return solver.step(block.system, state, 1e-3);
  };
  for (const auto& [dropped, withMiddle] :
       {std::pair{3, false}, std::pair{0, true}, std::pair{4, true}}) {
    QuasiNewtonSolver kept(settings);
    MechanicalState state = block.system.restState();
    for (int n = 0; n < 5; ++n) stepWith(kept, state, 0, false);
    ASSERT_EQ(kept.factorisationCount(), 1);
    MechanicalState fresh = state;
    QuasiNewtonSolver refactorised(settings);
    stepWith(kept, state, dropped, withMiddle);
    stepWith(refactorised, fresh, dropped, withMiddle);
    EXPECT_EQ(kept.factorisationCount(), 1) << dropped;  // 3 to 13 changes: through Woodbury
    const double moved = (state.x - block.mesh.restPositions_m).cwiseAbs().maxCoeff();
    EXPECT_GT(moved, 1e-7);
    EXPECT_LT((state.x - fresh.x).cwiseAbs().maxCoeff(), 1e-9 * moved)
        << dropped << " dropped, middle layer " << withMiddle;
  }
}

TEST(QuasiNewton, MoreSupportChangesThanTheLimitRefactoriseH0) {
  test::BlockSystem block({0.03, 0.03, 0.03}, {3, 3, 3});
  block.system.gravity.acceleration_m_s2 = kGravity;
  IntegratorSettings settings;
  settings.maxIterations = 2;
  QuasiNewtonSolver solver(settings);
  MechanicalState state = block.system.restState();
  addSupportContacts(block.system, block.mesh, 0.0);  // 16 points
  solver.step(block.system, state, 1e-3);
  addSupportContacts(block.system, block.mesh, 0.01);  // 16 more: at the limit
  solver.step(block.system, state, 1e-3);
  EXPECT_EQ(solver.factorisationCount(), 1);
  addSupportContacts(block.system, block.mesh, 0.02);  // 32 changes
  solver.step(block.system, state, 1e-3);
  EXPECT_EQ(solver.factorisationCount(), 2);
  solver.step(block.system, state, 1e-3);  // the same support again: carried
  EXPECT_EQ(solver.factorisationCount(), 2);
}

TEST(VolumeTerm, CompressedToSeventyPercentTheBlockRecoversWithNoInvertedTet) {
  const double height = 0.01;
  test::BlockSystem block({0.01, 0.01, height}, {2, 2, 2}, SpringLaw::Eesm, false, 20e3);
  MechanicalSystem& system = block.system;
  std::vector<int> bottom, top;
  for (Eigen::Index i = 0; i < block.mesh.nodeCount(); ++i) {
    if (block.mesh.restPositions_m(2, i) < 1e-12) bottom.push_back(static_cast<int>(i));
    if (block.mesh.restPositions_m(2, i) > height - 1e-12) top.push_back(static_cast<int>(i));
  }
  for (const int node : bottom) system.fixNode(node);
  for (const int node : top) system.fixDof(node, 2);
  IntegratorSettings settings;
  settings.massDamping_1_s = 50.0;
  settings.forceTolerance_N = 1e-9;
  ImplicitEulerSolver integrator(settings, LinearSolverKind::Cholesky);
  MechanicalState state = system.restState();
  const double dt = 1e-3;
  for (int n = 1; n <= 100; ++n) {  // press the top face down to 0.7 H over 0.1 s
    for (const int node : top) state.x(2, node) = height * (1.0 - 0.3 * n / 100.0);
    ASSERT_TRUE(integrator.step(system, state, dt).isFinite);
  }
  EXPECT_EQ(VolumeForceField::inspect(block.mesh, state.x).invertedTetCount, 0);
  system.releaseAll();
  for (const int node : bottom) system.fixNode(node);
  for (int n = 0; n < 1500; ++n) ASSERT_TRUE(integrator.step(system, state, dt).isFinite);
  double meanTop = 0.0;
  for (const int node : top) meanTop += state.x(2, node) / static_cast<double>(top.size());
  EXPECT_NEAR(meanTop, height, 0.01 * height);
  EXPECT_EQ(VolumeForceField::inspect(block.mesh, state.x).invertedTetCount, 0);
}

TEST(Slivers, AMeshWithASliverTetSimulatesFinitely) {
  TetMesh mesh = makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1});
  // A ninth node just off the face x = 0 and a flat tet onto it: a sliver.
  mesh.nodes_m.conservativeResize(3, 9);
  mesh.nodes_m.col(8) << -1e-6, 0.005, 0.005;
  mesh.tets.conservativeResize(4, 7);
  mesh.tets.col(6) << 0, 2, 4, 8;
  if (signedTetVolume(mesh.nodes_m, mesh.tets, 6) < 0) std::swap(mesh.tets(1, 6), mesh.tets(2, 6));
  ASSERT_FALSE(inspectTets(mesh).slivers.empty());
  const auto& liver = test::LiverMaterial::instance();
  const SpringMesh springsMesh = buildSpringMesh(mesh, 1060.0);
  const SpringForceLaw law(SpringLaw::Eesm, liver.table, liver.parameters, 0.0, false);
  SpringForceField springs(springsMesh, law);
  MechanicalSystem system(springs, nullptr);
  system.gravity.acceleration_m_s2 = kGravity;
  system.fixNode(1);
  system.fixNode(3);
  IntegratorSettings settings;
  settings.massDamping_1_s = 5.0;
  ImplicitEulerSolver integrator(settings, LinearSolverKind::Cholesky);
  MechanicalState state = system.restState();
  for (int n = 0; n < 200; ++n) ASSERT_TRUE(integrator.step(system, state, 1e-3).isFinite);
}

// Meshes from kParallelNodePassMinimum nodes on run their node-wise passes (residual, external
// forces, predictor, velocities, the spring parts' sums) on the pool too; the smaller meshes of
// the other tests run them in order on the caller. Both integrators on a sagging, softening
// block of 9,261 nodes: the same state to the bit on one, two and three threads.
TEST(ParallelPasses, AMeshAboveTheNodePassMinimumStepsBitIdenticallyOnAnyThreadCount) {
  const auto run = [](const std::string& name, ForkJoinPool* pool) {
    test::BlockSystem block({0.1, 0.1, 0.1}, {20, 20, 20}, SpringLaw::Eesm, true);
    EXPECT_GE(block.mesh.nodeCount(), kParallelNodePassMinimum);
    block.system.gravity.acceleration_m_s2 = kGravity;
    for (Eigen::Index i = 0; i < block.mesh.nodeCount(); ++i) {
      if (block.mesh.restPositions_m(2, i) < 1e-12) block.system.fixNode(static_cast<int>(i));
    }
    block.springs.setThreadPool(pool);
    IntegratorSettings settings;
    settings.massDamping_1_s = 1.0;
    settings.maxIterations = 2;
    auto integrator = makeIntegrator(name, settings);
    MechanicalState state = block.system.restState();
    const double dt = name == "explicit"
                          ? SymplecticEulerSolver::stableTimeStep(block.system, state.x, 0.8)
                          : 1e-3;
    StepReport report;
    for (int n = 0; n < 4; ++n) {
      report = integrator->step(block.system, state, dt);
      EXPECT_TRUE(report.isFinite && !report.refused) << name << " step " << n;
    }
    block.springs.setThreadPool(nullptr);
    return std::tuple{state.x, state.v, Eigen::VectorXd(block.springs.lambdaMax()),
                      report.residual_N};
  };
  for (const std::string name : {"explicit", "implicit-cg"}) {
    const auto serial = run(name, nullptr);
    // It moved, and softening history was written: the passes had work to do.
    EXPECT_GT(std::get<1>(serial).cwiseAbs().maxCoeff(), 0.0) << name;
    EXPECT_GT(std::get<2>(serial).maxCoeff(), 1.0) << name;
    for (const int threads : {2, 3}) {
      ForkJoinPool pool(threads);
      const auto parallel = run(name, &pool);
      EXPECT_TRUE(std::get<0>(parallel) == std::get<0>(serial))
          << name << ", " << threads << " threads";
      EXPECT_TRUE(std::get<1>(parallel) == std::get<1>(serial))
          << name << ", " << threads << " threads";
      EXPECT_TRUE(std::get<2>(parallel) == std::get<2>(serial))
          << name << ", " << threads << " threads";
      EXPECT_EQ(std::get<3>(parallel), std::get<3>(serial))
          << name << ", " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace tissuesim
