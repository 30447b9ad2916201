// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringForceField.h"
#include "numerics/CpuFeatures.h"

#include <algorithm>
#include <random>
#include <tuple>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "support/TestSystems.h"

namespace tissuesim {
namespace {

/// A block with its nodes jiggled: springs stretched and compressed in every direction.
Eigen::Matrix3Xd deformed(const SpringMesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  const double h = mesh.restLength_m.minCoeff();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    for (int a = 0; a < 3; ++a) x(a, i) += amplitude * h * u(random);
  }
  return x;
}

double elasticEnergy(const SpringMesh& mesh, const Eigen::Matrix3Xd& x) {
  double energy = 0.0;
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    const double lambda =
        (x.col(mesh.springs(1, s)) - x.col(mesh.springs(0, s))).norm() / mesh.restLength_m[s];
    energy += mesh.volume_m3[s] * test::LiverMaterial::instance().table.energy(lambda);
  }
  return energy;
}

/// The dense 3#V by 3#V matrix of per-spring blocks K_e: [K, -K; -K, K] on each spring (a, b).
Eigen::MatrixXd denseStiffness(const SpringMesh& mesh, const AxialBlocks& blocks) {
  const Eigen::Index n = mesh.nodeCount();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    const Eigen::Matrix3d ks = axialBlock(blocks.col(s).data());
    const int a = mesh.springs(0, s), b = mesh.springs(1, s);
    k.block<3, 3>(3 * a, 3 * a) += ks;
    k.block<3, 3>(3 * b, 3 * b) += ks;
    k.block<3, 3>(3 * a, 3 * b) -= ks;
    k.block<3, 3>(3 * b, 3 * a) -= ks;
  }
  return k;
}

TEST(SpringForceField, ForceIsMinusTheEnergyGradient) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2});
  const Eigen::Matrix3Xd x = deformed(block.mesh, 0.15, 1);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  block.springs.addForces(x, f);
  const double h = 1e-8;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3Xd up = x, down = x;
      up(a, i) += h;
      down(a, i) -= h;
      const double gradient =
          (elasticEnergy(block.mesh, up) - elasticEnergy(block.mesh, down)) / (2 * h);
      worst = std::max(worst, std::abs(f(a, i) + gradient));
    }
  }
  EXPECT_LT(worst, 1e-5 * f.cwiseAbs().maxCoeff());
  // Newton's third law: internal forces sum to zero.
  EXPECT_LT(f.rowwise().sum().norm(), 1e-12 * f.cwiseAbs().maxCoeff());
}

TEST(SpringForceField, StiffnessIsTheForceJacobian) {
  for (const bool isSoftening : {false, true}) {
    test::BlockSystem block({0.02, 0.02, 0.02}, {1, 1, 1}, SpringLaw::Eesm, isSoftening);
    block.springs.commitStretchHistory(deformed(block.mesh, 0.2, 5));
    const Eigen::Matrix3Xd x = deformed(block.mesh, 0.15, 2);
    const Eigen::Index n = x.cols();
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, n);
    AxialBlocks blocks(5, block.mesh.springCount());
    block.springs.addForcesAndStiffness(x, f, blocks, /*isProjected=*/false);
    const Eigen::MatrixXd k = denseStiffness(block.mesh, blocks);
    const double h = 1e-9;
    for (Eigen::Index j = 0; j < 3 * n; ++j) {
      Eigen::Matrix3Xd up = x, down = x;
      up.data()[j] += h;
      down.data()[j] -= h;
      Eigen::Matrix3Xd fu = Eigen::Matrix3Xd::Zero(3, n), fd = Eigen::Matrix3Xd::Zero(3, n);
      block.springs.addForces(up, fu);
      block.springs.addForces(down, fd);
      const Eigen::VectorXd column = -(Eigen::Map<Eigen::VectorXd>(fu.data(), 3 * n) -
                                       Eigen::Map<Eigen::VectorXd>(fd.data(), 3 * n)) /
                                     (2 * h);
      EXPECT_LT((column - k.col(j)).cwiseAbs().maxCoeff(), 1e-4 * k.cwiseAbs().maxCoeff())
          << "column " << j << " softening " << isSoftening;
    }
  }
}

TEST(SpringForceField, ProjectedStiffnessIsPositiveSemiDefinite) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {1, 1, 1});
  const Eigen::Matrix3Xd x = deformed(block.mesh, 0.3, 3);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  AxialBlocks blocks(5, block.mesh.springCount());
  block.springs.addForcesAndStiffness(x, f, blocks, /*isProjected=*/true);
  for (Eigen::Index s = 0; s < blocks.cols(); ++s) {
    const Eigen::Matrix3d ks = axialBlock(blocks.col(s).data());
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(ks).eigenvalues().minCoeff(), -1e-9);
  }
}

TEST(SpringForceField, FrequencyBoundIsAnUpperBound) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 1});
  const Eigen::Matrix3Xd x = deformed(block.mesh, 0.1, 4);
  const Eigen::Index n = x.cols();
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, n);
  AxialBlocks blocks(5, block.mesh.springCount());
  block.springs.addForcesAndStiffness(x, f, blocks, false);
  const Eigen::MatrixXd k = denseStiffness(block.mesh, blocks);
  Eigen::VectorXd inverseRootMass(3 * n);
  for (Eigen::Index i = 0; i < n; ++i)
    inverseRootMass.segment<3>(3 * i).setConstant(1.0 / std::sqrt(block.mesh.nodeMass_kg[i]));
  const Eigen::MatrixXd scaled = inverseRootMass.asDiagonal() * k * inverseRootMass.asDiagonal();
  const double omega2 =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(scaled).eigenvalues().cwiseAbs().maxCoeff();
  const double bound = block.springs.frequencySquaredBound(x);
  EXPECT_GE(bound, omega2);
  EXPECT_LT(bound, 20.0 * omega2);  // and not uselessly loose
}

TEST(SpringForceField, StretchHistoryOnlyGrowsAndResets) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {1, 1, 1}, SpringLaw::Eesm, true);
  block.springs.commitStretchHistory(block.mesh.restPositions_m * 1.1);
  EXPECT_NEAR(block.springs.lambdaMax().minCoeff(), 1.1, 1e-12);
  block.springs.commitStretchHistory(block.mesh.restPositions_m * 1.05);
  EXPECT_NEAR(block.springs.lambdaMax().minCoeff(), 1.1, 1e-12);
  block.springs.resetStretchHistory();
  EXPECT_EQ(block.springs.lambdaMax().maxCoeff(), 1.0);
}

TEST(SpringForceField, AStretchJustAboveThePeakIsRecorded) {
  // The commit screens springs on squared stretches; one a hair (1e-12) above its peak must still
  // be recorded, at the force pass's exact stretch.
  test::BlockSystem block({0.02, 0.02, 0.02}, {2, 2, 2}, SpringLaw::Eesm, true);
  const Eigen::Matrix3Xd x = deformed(block.mesh, 0.2, 4);
  block.springs.commitStretchHistory(x);
  const Eigen::VectorXd first = block.springs.lambdaMax();
  const Eigen::Matrix3Xd hair = x * (1.0 + 1e-12);  // every length up by 1e-12
  block.springs.commitStretchHistory(hair);
  int raised = 0;
  for (Eigen::Index s = 0; s < block.mesh.springCount(); ++s) {
    const double exact =
        (hair.col(block.mesh.springs(1, s)) - hair.col(block.mesh.springs(0, s))).norm() *
        (1.0 / block.mesh.restLength_m[s]);
    if (first[s] > 1.0) {
      EXPECT_EQ(block.springs.lambdaMax()[s], std::max(first[s], exact)) << "spring " << s;
      raised += block.springs.lambdaMax()[s] > first[s] ? 1 : 0;
    }
  }
  EXPECT_GT(raised, 10);
}

TEST(SpringForceField, RecordingTheStretchesChangesNothingAtTheSameState) {
  // Every stretched spring sets its peak here, and at the same positions it must stay on its
  // virgin curve: forces and stiffness bit-identical before and after the commit. A peak even one
  // unit in the last place above the pass's own stretch would put it just below lambda_max,
  // where the softened tangent is nearly vertical.
  test::BlockSystem block({0.02, 0.02, 0.02}, {3, 3, 3}, SpringLaw::Eesm, true);
  for (const unsigned seed : {1u, 2u, 3u}) {
    block.springs.resetStretchHistory();
    const Eigen::Matrix3Xd x = deformed(block.mesh, 0.2, seed);
    Eigen::Matrix3Xd before = Eigen::Matrix3Xd::Zero(3, x.cols());
    Eigen::Matrix3Xd after = before;
    AxialBlocks blocksBefore(5, block.mesh.springCount());
    AxialBlocks blocksAfter(5, block.mesh.springCount());
    block.springs.addForcesAndStiffness(x, before, blocksBefore);
    block.springs.commitStretchHistory(x);
    ASSERT_GT(block.springs.lambdaMax().maxCoeff(), 1.05) << "the state stretches springs";
    block.springs.addForcesAndStiffness(x, after, blocksAfter);
    EXPECT_EQ(before, after) << "seed " << seed;
    EXPECT_EQ(blocksBefore, blocksAfter) << "seed " << seed;
  }
}

TEST(SpringForceField, TheCommitFromThePassEqualsTheOneComputed) {
  // After a pass at x the commit takes that pass's stretches (batched groups, scalar springs
  // past the usable range, a collapsed spring); after a pass elsewhere it computes them. Both
  // must set the same peaks, to the bit, with or without the batched law.
  for (const bool isBatched : {true, false}) {
    test::BlockSystem recorded({0.02, 0.02, 0.02}, {3, 3, 3}, SpringLaw::Eesm, true);
    test::BlockSystem computed({0.02, 0.02, 0.02}, {3, 3, 3}, SpringLaw::Eesm, true);
    recorded.springs.setBatched(isBatched);
    computed.springs.setBatched(isBatched);
    for (const unsigned seed : {1u, 2u}) {
      Eigen::Matrix3Xd x = deformed(recorded.mesh, 0.2, seed);
      x.col(0) -= Eigen::Vector3d(0.015, 0.0, 0.0);  // springs past the usable range
      x.col(5) = x.col(4);                           // and a collapsed one
      Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
      recorded.springs.addForces(x, f);
      recorded.springs.commitStretchHistory(x);
      const Eigen::Matrix3Xd elsewhere = x * 1.01;
      computed.springs.addForces(elsewhere, f);
      computed.springs.commitStretchHistory(x);
      ASSERT_GT(recorded.springs.lambdaMax().maxCoeff(), 1.05) << "the state stretches springs";
      EXPECT_EQ(recorded.springs.lambdaMax(), computed.springs.lambdaMax())
          << seed << " " << isBatched;
    }
  }
}

TEST(SpringForceField, TheForceOnlyPassGivesTheSameForces) {
  // It evaluates the law without slopes: the forces must still be those of the pass with
  // stiffness, to the bit, on every branch (virgin, softened, compressed after stretching,
  // past the usable range), for every law.
  for (const SpringLaw law : {SpringLaw::Eesm, SpringLaw::EesmPaper, SpringLaw::Smm}) {
    test::BlockSystem block({0.02, 0.02, 0.02}, {3, 3, 3}, law, true);
    block.springs.commitStretchHistory(deformed(block.mesh, 0.25, 5));
    Eigen::Matrix3Xd x = deformed(block.mesh, 0.2, 6);
    x.col(0) -= Eigen::Vector3d(0.015, 0.0, 0.0);  // a few springs past the usable range
    Eigen::Matrix3Xd withStiffness = Eigen::Matrix3Xd::Zero(3, x.cols());
    Eigen::Matrix3Xd forceOnly = withStiffness;
    AxialBlocks blocks(5, block.mesh.springCount());
    const SpringFieldReport full = block.springs.addForcesAndStiffness(x, withStiffness, blocks);
    const SpringFieldReport only = block.springs.addForces(x, forceOnly);
    EXPECT_EQ(forceOnly, withStiffness) << static_cast<int>(law);
    EXPECT_EQ(only.beyondRangeCount, full.beyondRangeCount);
    if (law != SpringLaw::Smm) {
      EXPECT_GT(full.beyondRangeCount, 0);
    }
    EXPECT_LT(full.minStretch, 1.0);
  }
}

TEST(SpringForceField, AnInertNetworkKeepsItsStretchesAndAddsNoStiffness) {
  // The FEM's network (every V_e zero) is kept for its stretches: its passes must still report
  // them, and its products, blocks and assembly add nothing, so the solvers do not pay for it.
  SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.02, 0.02, 0.02}, {2, 2, 2}),
                                    test::LiverMaterial::instance().parameters.density_kg_m3);
  test::BlockSystem live({0.02, 0.02, 0.02}, {2, 2, 2});
  ASSERT_FALSE(live.springs.isInert());
  mesh.volume_m3.setZero();
  SpringForceField inert(mesh, live.law);
  ASSERT_TRUE(inert.isInert());
  const Eigen::Matrix3Xd x = deformed(mesh, 0.2, 7);
  const Eigen::Index n = x.cols();
  for (SpringForceField* field : {&live.springs, &inert}) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    ForcePass pass;
    pass.stiffness = StiffnessSlot::Current;
    ForceReport report;
    field->addForces(x, f, pass, report);
    EXPECT_GT(report.springs.maxStretch, 1.05) << "the stretches are reported";
    field->prepareProducts({0, n / 4, n / 2, 3 * n / 4, n});
    const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(3 * x.cols(), 1.0, 2.0);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(v.size());
    for (int part = 0; part < ForceField::kParts; ++part)
      field->addStiffnessProduct(part, v.data(), y.data());
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    field->addDiagonalBlock(1, block);
    std::vector<Eigen::Index> work(static_cast<std::size_t>(x.cols()), 0);
    field->addProductWork(work);
    if (field == &inert) {
      EXPECT_TRUE(f.isZero(0.0));
      EXPECT_TRUE(y.isZero(0.0));
      EXPECT_TRUE(block.isZero(0.0));
      EXPECT_EQ(*std::max_element(work.begin(), work.end()), 0);
    } else {
      EXPECT_GT(f.norm(), 0.0);
      EXPECT_GT(y.norm(), 0.0);
      EXPECT_GT(block.norm(), 0.0);
      EXPECT_GT(*std::max_element(work.begin(), work.end()), 0);
    }
  }
}

TEST(SpringForceField, TheBatchedLawAgreesWithTheScalarOne) {
  // Four springs at a time in AVX (SpringStressBatch.h) against the scalar law, on every branch:
  // virgin, softened, compressed after stretching, within the jump's fade below the peak (the
  // state just short of the one that set the peaks), and past the usable range (the scalar
  // law for that group). Not to the bit (its own exp and FMAs), to 1e-12 of the largest value.
  if (!hasAvxAndFma())
    GTEST_SKIP() << "this CPU has no AVX with FMA: the batched law is never used";
  test::BlockSystem block({0.02, 0.02, 0.02}, {3, 3, 3}, SpringLaw::Eesm, true);
  const Eigen::Matrix3Xd peaks = deformed(block.mesh, 0.25, 5);
  block.springs.commitStretchHistory(peaks);
  Eigen::Matrix3Xd past = deformed(block.mesh, 0.2, 6);
  past.col(0) -= Eigen::Vector3d(0.015, 0.0, 0.0);  // a few springs past the usable range
  const Eigen::Matrix3Xd rest = block.mesh.restPositions_m;
  const Eigen::Matrix3Xd justShort = rest + (1.0 - 2e-4) * (peaks - rest);
  int fading = 0;
  for (Eigen::Index s = 0; s < block.mesh.springCount(); ++s) {
    const double lambda =
        (justShort.col(block.mesh.springs(1, s)) - justShort.col(block.mesh.springs(0, s))).norm() /
        block.mesh.restLength_m[s];
    const double below = block.springs.lambdaMax()[s] - lambda;
    fading += lambda > 1.0 && below > 0.0 && below < SpringForceLaw::kJumpBlendWidth ? 1 : 0;
  }
  ASSERT_GT(fading, 10) << "springs within the jump's fade";
  for (const Eigen::Matrix3Xd& x : {past, justShort}) {
    Eigen::Matrix3Xd forces[2];
    AxialBlocks blocks[2];
    Eigen::VectorXd nodeStiffness[2];
    for (const bool isBatched : {true, false}) {
      ASSERT_EQ(block.springs.setBatched(isBatched), isBatched);
      const int i = isBatched ? 0 : 1;
      forces[i] = Eigen::Matrix3Xd::Zero(3, x.cols());
      blocks[i].resize(5, block.mesh.springCount());
      block.springs.addForcesAndStiffness(x, forces[i], blocks[i]);
      Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, x.cols());
      nodeStiffness[i].resize(x.cols());
      block.springs.addForcesAndNodeStiffness(x, scratch, nodeStiffness[i]);
    }
    EXPECT_LT((forces[0] - forces[1]).cwiseAbs().maxCoeff(),
              1e-12 * forces[1].cwiseAbs().maxCoeff());
    // Compared as full 3x3 blocks: the directions' rows are O(1), the stiffnesses' far larger.
    Eigen::Matrix<double, 9, Eigen::Dynamic> full[2];
    for (int i = 0; i < 2; ++i) {
      full[i].resize(9, blocks[i].cols());
      for (Eigen::Index s = 0; s < blocks[i].cols(); ++s) {
        full[i].col(s) = axialBlock(blocks[i].col(s).data()).reshaped();
      }
    }
    EXPECT_LT((full[0] - full[1]).cwiseAbs().maxCoeff(), 1e-12 * full[1].cwiseAbs().maxCoeff());
    EXPECT_LT((nodeStiffness[0] - nodeStiffness[1]).cwiseAbs().maxCoeff(),
              1e-12 * nodeStiffness[1].cwiseAbs().maxCoeff());
    EXPECT_NE(forces[0], forces[1]) << "the batched law ran (it rounds differently)";
  }
}

TEST(SpringForceField, CollapsedAndOverstretchedSpringsAreReported) {
  test::BlockSystem block({0.02, 0.02, 0.02}, {1, 1, 1});
  Eigen::Matrix3Xd x = block.mesh.restPositions_m;
  x.col(1) = x.col(0);  // spring (0, 1) has zero length
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  SpringFieldReport report = block.springs.addForces(x, f);
  EXPECT_EQ(report.collapsedCount, 1);
  EXPECT_TRUE(f.allFinite());
  x = block.mesh.restPositions_m;
  x.row(0) *= 1.8;  // past locking along x
  f.setZero();
  report = block.springs.addForces(x, f);
  EXPECT_GT(report.beyondRangeCount, 0);
  EXPECT_NEAR(report.maxStretch, 1.8, 1e-12);
  EXPECT_TRUE(f.allFinite());
}

TEST(SpringForceField, ResultsDoNotDependOnTheThreadCount) {
  // Softening on and a stretch history: every branch of the law runs in every part.
  test::BlockSystem block({0.03, 0.03, 0.03}, {4, 4, 4}, SpringLaw::Eesm, true);
  block.springs.commitStretchHistory(deformed(block.mesh, 0.2, 7));
  const Eigen::Matrix3Xd x = deformed(block.mesh, 0.15, 11);
  const auto evaluate = [&](ForkJoinPool* pool) {
    block.springs.setThreadPool(pool);
    Eigen::Matrix3Xd f =
        Eigen::Matrix3Xd::Constant(3, x.cols(), 0.25);  // added to, not overwritten
    Eigen::VectorXd stiffness(x.cols());
    const SpringFieldReport report = block.springs.addForcesAndNodeStiffness(x, f, stiffness);
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
    AxialBlocks blocks(5, block.mesh.springCount());
    block.springs.addForcesAndStiffness(x, g, blocks);
    block.springs.setThreadPool(nullptr);
    return std::tuple{f, stiffness, g, blocks, report};
  };
  const auto serial = evaluate(nullptr);
  EXPECT_GT(std::get<0>(serial).cwiseAbs().maxCoeff(), 0.25);  // forces were added
  for (const int threads : {2, 3, 4}) {
    ForkJoinPool pool(threads);
    const auto parallel = evaluate(&pool);
    // Bit-identical, not merely close: the partition and summation order are fixed.
    EXPECT_TRUE(std::get<0>(parallel) == std::get<0>(serial)) << threads;
    EXPECT_TRUE(std::get<1>(parallel) == std::get<1>(serial)) << threads;
    EXPECT_TRUE(std::get<2>(parallel) == std::get<2>(serial)) << threads;
    EXPECT_TRUE(std::get<3>(parallel) == std::get<3>(serial)) << threads;
    EXPECT_EQ(std::get<4>(parallel).minStretch, std::get<4>(serial).minStretch);
    EXPECT_EQ(std::get<4>(parallel).maxStretch, std::get<4>(serial).maxStretch);
  }
  // And the parts together are the whole: the same forces as a plain per-spring sum.
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Constant(3, x.cols(), 0.25);
  for (Eigen::Index s = 0; s < block.mesh.springCount(); ++s) {
    const int a = block.mesh.springs(0, s), b = block.mesh.springs(1, s);
    const Eigen::Vector3d d = x.col(b) - x.col(a);
    const double lambda = d.norm() / block.mesh.restLength_m[s];
    const double stress = block.law.evaluate(lambda, block.springs.lambdaMax()[s]).stress;
    const Eigen::Vector3d f =
        block.mesh.volume_m3[s] / block.mesh.restLength_m[s] * stress * d.normalized();
    expected.col(a) += f;
    expected.col(b) -= f;
  }
  EXPECT_LT((expected - std::get<0>(serial)).cwiseAbs().maxCoeff(),
            1e-12 * expected.cwiseAbs().maxCoeff());

  // The stretch history committed on a pool: every spring's peak as the serial commit sets it.
  const auto commitTwice = [&](ForkJoinPool* pool) {
    block.springs.setThreadPool(pool);
    block.springs.resetStretchHistory();
    block.springs.commitStretchHistory(deformed(block.mesh, 0.2, 7));
    block.springs.commitStretchHistory(deformed(block.mesh, 0.25, 13));
    block.springs.setThreadPool(nullptr);
    return block.springs.lambdaMax();
  };
  const Eigen::VectorXd serialPeaks = commitTwice(nullptr);
  EXPECT_GT((serialPeaks.array() > 1.0).count(), serialPeaks.size() / 4);  // many peaks set
  for (const int threads : {2, 3}) {
    ForkJoinPool pool(threads);
    EXPECT_EQ(commitTwice(&pool), serialPeaks) << threads << " threads";
  }
}

}  // namespace
}  // namespace tissuesim
