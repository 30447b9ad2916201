// SPDX-License-Identifier: Apache-2.0
// The matrix-free Newton operator against the assembled matrix it stands for, its parts'
// independence of the thread count, and Newton with it against Newton with Cholesky.

#include "system/SystemOperator.h"

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "integrators/ImplicitEulerSolver.h"
#include "numerics/BlockConjugateGradient.h"
#include "parallel/ForkJoinPool.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

Eigen::Matrix3Xd jiggled(const SpringMesh& mesh, double amplitude_m, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-amplitude_m, amplitude_m);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.row(2) *= 1.15;  // stretched along z: springs on their stiffening branch
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += uniform(random);
  return x;
}

// Everything the operator carries: the springs' and the volume term's stiffness at a deformed
// state, inertia weight and shift, a fixed node and a single fixed DOF, and three contacts pushed
// in (two sharing nodes and the fixed DOF, one carried by a tet's four nodes).
struct OperatorCase {
  static constexpr double kCellEdge_m = 0.03 / 4;
  test::BlockSystem block{{0.03, 0.03, 0.03}, {4, 4, 4}, SpringLaw::Eesm, false, 5e4};
  Eigen::Matrix3Xd x = jiggled(block.mesh, 5e-4, 3);
  double massWeight = 1e6;  // (1 + alpha h) / h^2 at h = 1 ms
  double shift = 3.5;

  OperatorCase() {
    // Contacts on tet nodes (joined by springs, as a contact's must be: the matrix's pattern).
    const Eigen::Vector4i middle = block.mesh.tets.col(block.mesh.tets.cols() / 2);
    const Eigen::Vector4i other = block.mesh.tets.col(block.mesh.tets.cols() / 3);
    block.system.fixNode(7);
    block.system.fixDof(middle[1], 1);
    const auto contact = [&](std::array<int, kMaxTermNodes> at, Eigen::Vector4d weights,
                             Eigen::Vector3d normal, double k) {
      PenaltyContact c;
      c.nodes = at;
      c.weights = weights;
      c.normal = normal.normalized();
      c.offset_m = c.normal.dot(c.point(x)) - 1e-3;  // 1 mm in at x
      c.stiffness_N_m = k;
      block.system.contacts.add(c);
    };
    contact({middle[0], middle[1], middle[2], middle[0]}, {0.5, 0.3, 0.2, 0.0}, {0.1, 1.0, 0.3},
            1e4);
    contact({middle[1], middle[2], middle[3], middle[1]}, {0.2, 0.2, 0.6, 0.0}, {-0.3, 0.2, 1.0},
            2e4);
    // A point on the drawn surface: carried by a tet's four nodes.
    contact({other[0], other[1], other[2], other[3]}, {0.1, 0.4, 0.3, 0.2}, {0.7, -0.2, 0.5}, 3e4);
  }

  /// The operator, with every field's stiffness at x in its current slot.
  std::unique_ptr<SystemOperator> makeOperator() {
    auto a = std::make_unique<SystemOperator>(block.system);
    Eigen::Matrix3Xd f(3, x.cols());
    block.system.forces(x, f, {StiffnessSlot::Current});
    a->setDiagonal(massWeight, shift);
    a->setFixedDofs(block.system.fixedDofs());
    return a;
  }

  /// The same system written out by hand (dense): the springs' blocks from their own pass, the
  /// volume term's k g g^T per cube and the contacts' k u u^T from their formulas, when asked for.
  Eigen::MatrixXd dense(bool withVolume, bool withContacts) const {
    NodeBlockMatrix m = block.system.makeMatrix();
    AxialBlocks blocks(5, block.mesh.springCount());
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    block.springs.addForcesAndStiffness(x, f, blocks);
    m.assignAxialEdgeStiffness(blocks);
    for (Eigen::Index i = 0; i < block.mesh.nodeCount(); ++i) {
      m.addToDiagonal(static_cast<int>(i), massWeight * block.mesh.nodeMass_kg[i] + shift);
    }
    Eigen::MatrixXd dense(m.matrix());
    // The volume term per lattice cube (VolumeCells.h): k g g^T with g = dV/dx summed over
    // the cube's tets, g_i of a tet = a third of the area vector of the face opposite node i.
    std::map<std::array<long, 3>, std::pair<Eigen::VectorXd, double>> cubes;  // {g, V0}
    for (Eigen::Index t = 0; withVolume && t < block.mesh.tets.cols(); ++t) {
      const auto p = [&](int i) -> Eigen::Vector3d { return x.col(block.mesh.tets(i, t)); };
      Eigen::Matrix<double, 12, 1> g;
      g.segment<3>(0) = (p(3) - p(1)).cross(p(2) - p(1)) / 6.0;
      g.segment<3>(3) = (p(2) - p(0)).cross(p(3) - p(0)) / 6.0;
      g.segment<3>(6) = (p(3) - p(0)).cross(p(1) - p(0)) / 6.0;
      g.segment<3>(9) = (p(1) - p(0)).cross(p(2) - p(0)) / 6.0;
      auto& [cubeGradient, restVolume] = cubes[test::cubeOfTet(block.mesh, t, kCellEdge_m)];
      if (cubeGradient.size() == 0) cubeGradient = Eigen::VectorXd::Zero(dense.rows());
      for (int i = 0; i < 4; ++i)
        cubeGradient.segment<3>(3 * block.mesh.tets(i, t)) += g.segment<3>(3 * i);
      restVolume += block.mesh.tetRestVolume_m3[t];
    }
    for (const auto& [cube, cell] : cubes)
      dense += block.volume->bulkModulus() / cell.second * cell.first * cell.first.transpose();
    for (const PenaltyContact& c : block.system.contacts.contacts()) {
      if (!withContacts) break;
      Eigen::VectorXd u = Eigen::VectorXd::Zero(dense.rows());
      for (std::size_t i = 0; i < kMaxTermNodes; ++i)
        u.segment<3>(3 * c.nodes[i]) += c.weights[static_cast<Eigen::Index>(i)] * c.normal;
      dense += c.stiffness_N_m * u * u.transpose();
    }
    const std::vector<char>& fixed = block.system.fixedDofs();
    for (std::size_t d = 0; d < fixed.size(); ++d) {
      if (fixed[d] == 0) continue;
      dense.row(static_cast<Eigen::Index>(d)).setZero();
      dense.col(static_cast<Eigen::Index>(d)).setZero();
      dense(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(d)) = 1.0;
    }
    return dense;
  }

  /// Random, zero on the fixed DOFs (the product's precondition).
  Eigen::VectorXd randomDirection(unsigned seed) const {
    const std::vector<char>& fixed = block.system.fixedDofs();
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd direction(static_cast<Eigen::Index>(fixed.size()));
    for (Eigen::Index d = 0; d < direction.size(); ++d)
      direction[d] = fixed[static_cast<std::size_t>(d)] != 0 ? 0.0 : uniform(random);
    return direction;
  }
};

Eigen::VectorXd multiply(const SystemOperator& a, const Eigen::VectorXd& x,
                         bool isReversed = false) {
  Eigen::VectorXd y = Eigen::VectorXd::Constant(x.size(), std::nan(""));
  for (int p = 0; p < BlockLinearOperator::kParts; ++p) {
    a.multiplyPart(isReversed ? BlockLinearOperator::kParts - 1 - p : p, x.data(), y.data());
  }
  return y;
}

TEST(SystemOperator, IsTheAssembledMatrix) {
  OperatorCase c;
  const std::unique_ptr<SystemOperator> a = c.makeOperator();
  const Eigen::MatrixXd dense = c.dense(true, true);
  const double scale = dense.cwiseAbs().maxCoeff();
  // The parts cover every node once, in order.
  const BlockLinearOperator::PartBounds& bounds = a->partBounds();
  EXPECT_EQ(bounds.front(), 0);
  EXPECT_EQ(bounds.back(), c.block.mesh.nodeCount());
  for (int p = 0; p < BlockLinearOperator::kParts; ++p) EXPECT_LT(bounds[p], bounds[p + 1]) << p;
  for (const unsigned seed : {1u, 2u}) {
    const Eigen::VectorXd x = c.randomDirection(seed);
    const Eigen::VectorXd y = multiply(*a, x);
    ASSERT_TRUE(y.allFinite()) << "every row written";
    EXPECT_LT((y - dense * x).cwiseAbs().maxCoeff(), 1e-12 * scale * x.cwiseAbs().sum()) << seed;
  }
  // The preconditioner's blocks, and the shift's scale.
  double largest = 0.0;
  for (Eigen::Index j = 0; j < a->nodeCount(); ++j) {
    const Eigen::Matrix3d expected = dense.block<3, 3>(3 * j, 3 * j);
    EXPECT_LT((a->diagonalBlock(j) - expected).cwiseAbs().maxCoeff(), 1e-12 * scale)
        << "node " << j;
    largest = std::max(largest, expected.diagonal().maxCoeff());
  }
  EXPECT_NEAR(a->largestDiagonalEntry(), largest, 1e-12 * largest);
  // The contacts and the volume term matter here (the comparison would fail without either).
  const Eigen::VectorXd x = c.randomDirection(1);
  EXPECT_GT((multiply(*a, x) - c.dense(true, false) * x).cwiseAbs().maxCoeff(), 1.0);
  EXPECT_GT((multiply(*a, x) - c.dense(false, true) * x).cwiseAbs().maxCoeff(), 1.0);
}

// The same operator with its true diagonal blocks as the preconditioner's: plain block Jacobi.
class PlainBlockJacobi final : public BlockLinearOperator {
 public:
  explicit PlainBlockJacobi(const SystemOperator& a) : m_a(a) {}
  Eigen::Index nodeCount() const override { return m_a.nodeCount(); }
  const PartBounds& partBounds() const override { return m_a.partBounds(); }
  void multiplyPart(int part, const double* x, double* y) const override {
    m_a.multiplyPart(part, x, y);
  }
  Eigen::Matrix3d diagonalBlock(Eigen::Index j) const override { return m_a.diagonalBlock(j); }

 private:
  const SystemOperator& m_a;
};

TEST(SystemOperator, TheVolumeTermsWeighedBlocksShortenCgToTheSameSolution) {
  OperatorCase c;
  const std::unique_ptr<SystemOperator> a = c.makeOperator();
  // The preconditioner's blocks: the diagonal's, the volume term's part weighed by sqrt(8)
  // (every cell a cube of 8 nodes); nodes with a fixed DOF left out (their rows are replaced).
  const std::vector<char>& fixed = c.block.system.fixedDofs();
  int compared = 0;
  for (Eigen::Index j = 0; j < a->nodeCount(); ++j) {
    const auto row = static_cast<std::size_t>(3 * j);
    if (fixed[row] != 0 || fixed[row + 1] != 0 || fixed[row + 2] != 0) continue;
    Eigen::Matrix3d volumePart = Eigen::Matrix3d::Zero();
    c.block.volume->addDiagonalBlock(j, volumePart);
    const Eigen::Matrix3d expected = a->diagonalBlock(j) + (std::sqrt(8.0) - 1.0) * volumePart;
    EXPECT_LT((a->preconditionerBlock(j) - expected).cwiseAbs().maxCoeff(),
              1e-12 * expected.cwiseAbs().maxCoeff())
        << "node " << j;
    ++compared;
  }
  EXPECT_GT(compared, 100);
  // CG to a tight tolerance: the same solution, in fewer iterations than with plain blocks.
  const Eigen::VectorXd b = c.randomDirection(4);
  BlockConjugateGradient cg;
  Eigen::VectorXd weighed, plain;
  const ConjugateGradientReport withWeights = cg.solve(*a, b, weighed, 1e-10, 2000);
  const ConjugateGradientReport without = cg.solve(PlainBlockJacobi(*a), b, plain, 1e-10, 2000);
  ASSERT_TRUE(withWeights.converged);
  ASSERT_TRUE(without.converged);
  EXPECT_LT((weighed - plain).norm(), 1e-8 * plain.norm());
  EXPECT_LT(withWeights.iterations, without.iterations)
      << "CG iterations, the volume term's blocks weighed / plain";
}

TEST(SystemOperator, TheFieldsAssembleWhatTheOperatorApplies) {
  // The direct solver's path: every field's addStiffness into the system's pattern.
  OperatorCase c;
  const std::unique_ptr<SystemOperator> a = c.makeOperator();
  NodeBlockMatrix m = c.block.system.makeMatrix();
  c.block.system.assembleStiffness(m);
  for (Eigen::Index i = 0; i < c.block.mesh.nodeCount(); ++i)
    m.addToDiagonal(static_cast<int>(i), c.massWeight * c.block.mesh.nodeMass_kg[i] + c.shift);
  m.applyFixedDofs(c.block.system.fixedDofs());
  const Eigen::MatrixXd dense = c.dense(true, true);
  EXPECT_LT((Eigen::MatrixXd(m.matrix()) - dense).cwiseAbs().maxCoeff(),
            1e-12 * dense.cwiseAbs().maxCoeff());
}

TEST(SystemOperator, AnAcceptedTrialIsTheStiffnessAtTheTrial) {
  // Current at x, a trial at x2, accepted: the operator applies K at x2, as a pass at x2 would.
  OperatorCase c;
  const std::unique_ptr<SystemOperator> a = c.makeOperator();
  const Eigen::Matrix3Xd x2 = jiggled(c.block.mesh, 5e-4, 11);
  Eigen::Matrix3Xd f(3, x2.cols());
  const Eigen::VectorXd direction = c.randomDirection(4);
  const Eigen::VectorXd atX = multiply(*a, direction);
  c.block.system.forces(x2, f, {StiffnessSlot::Trial});
  EXPECT_EQ(multiply(*a, direction), atX) << "a trial pass leaves the current slot alone";
  c.block.system.acceptTrialStiffness();
  const Eigen::VectorXd accepted = multiply(*a, direction);
  c.block.system.forces(x2, f, {StiffnessSlot::Current});
  EXPECT_EQ(accepted, multiply(*a, direction));
  EXPECT_GT((accepted - atX).cwiseAbs().maxCoeff(), 1e-3) << "x and x2 differ in stiffness";
}

TEST(SystemOperator, PartsAreIndependentOfOrderAndThreads) {
  OperatorCase c;
  const std::unique_ptr<SystemOperator> a = c.makeOperator();
  const Eigen::VectorXd x = c.randomDirection(5);
  const Eigen::VectorXd expected = multiply(*a, x);
  EXPECT_EQ(multiply(*a, x, /*isReversed=*/true), expected);
  for (const int threads : {2, 4}) {
    ForkJoinPool pool(threads);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
    runParts(&pool, BlockLinearOperator::kParts,
             [&](int p) { a->multiplyPart(p, x.data(), y.data()); });
    EXPECT_EQ(y, expected) << threads << " threads";
  }
}

// One implicit Euler step of a clamped block pressed by a contact and pulled by gravity, with and
// without the volume term, converged tightly: CG on the matrix-free operator and Cholesky on the
// assembled matrix reach the same state.
TEST(SystemOperator, NewtonWithItMatchesCholesky) {
  for (const double bulkModulus : {0.0, 2e4}) {
    test::BlockSystem block({0.03, 0.03, 0.03}, {3, 3, 3}, SpringLaw::Eesm, false, bulkModulus);
    for (int node = 0; node < 16; ++node) block.system.fixNode(node);  // the z = 0 face
    block.system.gravity.acceleration_m_s2 = Eigen::Vector3d(0.0, 0.0, -9.81);
    MechanicalState start = block.system.restState();
    // A surface triangle on the top face: three nodes of one tet there (joined by springs).
    PenaltyContact contact;
    const double zTop = block.mesh.restPositions_m.row(2).maxCoeff();
    for (Eigen::Index t = 0; t < block.mesh.tets.cols(); ++t) {
      std::vector<int> onTop;
      for (int i = 0; i < 4; ++i) {
        if (block.mesh.restPositions_m(2, block.mesh.tets(i, t)) > zTop - 1e-9)
          onTop.push_back(block.mesh.tets(i, t));
      }
      if (onTop.size() == 3) {
        contact.nodes = {onTop[0], onTop[1], onTop[2], onTop[0]};
        break;
      }
    }
    ASSERT_NE(contact.nodes[0], contact.nodes[1]);
    contact.weights = {0.4, 0.3, 0.3, 0.0};
    contact.normal = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
    contact.offset_m = contact.normal.dot(contact.point(start.x)) - 2e-3;  // 2 mm in
    contact.stiffness_N_m = 1e4;
    block.system.contacts.add(contact);
    IntegratorSettings settings;
    settings.maxIterations = 30;
    settings.forceTolerance_N = 1e-10;
    settings.linearTolerance = 1e-12;
    MechanicalState cholesky = start, cg = start;
    const StepReport exact = ImplicitEulerSolver(settings, LinearSolverKind::Cholesky)
                                 .step(block.system, cholesky, 1e-3);
    const StepReport iterative = ImplicitEulerSolver(settings, LinearSolverKind::ConjugateGradient)
                                     .step(block.system, cg, 1e-3);
    ASSERT_TRUE(exact.converged) << bulkModulus;
    ASSERT_TRUE(iterative.converged) << bulkModulus;
    const double moved = (cholesky.x - start.x).cwiseAbs().maxCoeff();
    ASSERT_GT(moved, 1e-4) << "the contact pushed the block";
    EXPECT_LT((cg.x - cholesky.x).cwiseAbs().maxCoeff(), 1e-9 * moved) << bulkModulus;
  }
}

}  // namespace
}  // namespace tissuesim
