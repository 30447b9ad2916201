// The matrix-free Newton operator against the assembled matrix it stands for, its parts'
// independence of the thread count, and Newton with it against Newton with Cholesky.

#include "integrators/SpringSystemOperator.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "TestSystems.h"
#include "integrators/ImplicitEulerSolver.h"
#include "parallel/ForkJoinPool.h"

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

// Everything the operator carries: spring blocks and the volume term's at a deformed state,
// inertia weight and shift, a fixed node and a single fixed DOF, and two contact terms sharing a
// node (one across the parts' boundary region), each u zero on the fixed DOFs as
// PenaltyContacts makes it.
struct OperatorCase {
  test::BlockSystem block{{0.03, 0.03, 0.03}, {4, 4, 4}, SpringLaw::Eesm, false, 5e4};
  AxialBlocks blocks;
  VolumeBlocks volumeBlocks;
  std::vector<char> fixed;
  std::vector<RankOneTerm> terms;
  double massWeight = 1e6;  // (1 + alpha h) / h^2 at h = 1 ms
  double shift = 3.5;

  OperatorCase() {
    const Eigen::Matrix3Xd x = jiggled(block.mesh, 5e-4, 3);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    blocks.resize(5, block.mesh.springCount());
    block.springs.addForcesAndStiffness(x, f, blocks);
    volumeBlocks.resize(13, block.mesh.tets.cols());
    block.volume->addForces(x, f, &volumeBlocks);
    const Eigen::Index nodes = block.mesh.nodeCount();
    fixed.assign(static_cast<std::size_t>(3 * nodes), 0);
    for (int axis = 0; axis < 3; ++axis) fixed[static_cast<std::size_t>(3 * 7 + axis)] = 1;
    fixed[static_cast<std::size_t>(3 * (nodes / 2) + 1)] = 1;
    const auto term = [&](std::array<int, kMaxTermNodes> at, Eigen::Vector4d weights,
                          Eigen::Vector3d normal, double k) {
      RankOneTerm t;
      t.nodes = at;
      t.stiffness_N_m = k;
      for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
        for (int axis = 0; axis < 3; ++axis) {
          const bool isFree = fixed[static_cast<std::size_t>(3 * at[i] + axis)] == 0;
          t.blocks[i][axis] =
              isFree ? weights[static_cast<Eigen::Index>(i)] * normal.normalized()[axis] : 0.0;
        }
      }
      terms.push_back(t);
    };
    const int middle = static_cast<int>(nodes / 2);
    term({middle, middle + 1, middle + 5, middle}, {0.5, 0.3, 0.2, 0.0}, {0.1, 1.0, 0.3}, 1e4);
    term({middle + 1, 2, 3, middle + 1}, {0.2, 0.2, 0.6, 0.0}, {-0.3, 0.2, 1.0}, 2e4);
    // A point on the drawn surface: carried by a tet's four nodes.
    const Eigen::Vector4i tet = block.mesh.tets.col(block.mesh.tets.cols() / 3);
    term({tet[0], tet[1], tet[2], tet[3]}, {0.1, 0.4, 0.3, 0.2}, {0.7, -0.2, 0.5}, 3e4);
  }

  SpringSystemOperator makeOperator() const {
    SpringSystemOperator a(block.mesh);
    a.setSpringBlocks(blocks);
    a.setVolumeBlocks(&volumeBlocks);
    a.setDiagonal(massWeight, shift);
    a.setFixedDofs(fixed);
    a.setTerms(&terms);
    return a;
  }

  /// The same system assembled, as Newton assembles it (dense, for the comparison).
  Eigen::MatrixXd assembled() const {
    NodeBlockMatrix m = block.system.makeMatrix();
    m.assignAxialEdgeStiffness(blocks);
    for (Eigen::Index i = 0; i < block.mesh.nodeCount(); ++i) {
      m.addToDiagonal(static_cast<int>(i), massWeight * block.mesh.nodeMass_kg[i] + shift);
    }
    Eigen::MatrixXd dense(m.matrix());
    for (Eigen::Index t = 0; t < block.mesh.tets.cols(); ++t) {
      // c g g^T, g_i = dV/dx_i: a third of the area vector of the face opposite node i.
      const Eigen::Matrix3Xd x = jiggled(block.mesh, 5e-4, 3);
      const auto p = [&](int i) -> Eigen::Vector3d { return x.col(block.mesh.tets(i, t)); };
      Eigen::Matrix<double, 12, 1> g;
      g.segment<3>(0) = (p(3) - p(1)).cross(p(2) - p(1)) / 6.0;
      g.segment<3>(3) = (p(2) - p(0)).cross(p(3) - p(0)) / 6.0;
      g.segment<3>(6) = (p(3) - p(0)).cross(p(1) - p(0)) / 6.0;
      g.segment<3>(9) = (p(1) - p(0)).cross(p(2) - p(0)) / 6.0;
      const double c = block.volume->bulkModulus() / block.mesh.tetRestVolume_m3[t];
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          dense.block<3, 3>(3 * block.mesh.tets(i, t), 3 * block.mesh.tets(j, t)) +=
              c * g.segment<3>(3 * i) * g.segment<3>(3 * j).transpose();
        }
      }
    }
    for (const RankOneTerm& t : terms) {
      Eigen::VectorXd u = Eigen::VectorXd::Zero(dense.rows());
      for (std::size_t i = 0; i < kMaxTermNodes; ++i) u.segment<3>(3 * t.nodes[i]) += t.blocks[i];
      dense += t.stiffness_N_m * u * u.transpose();
    }
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
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd x(static_cast<Eigen::Index>(fixed.size()));
    for (Eigen::Index d = 0; d < x.size(); ++d)
      x[d] = fixed[static_cast<std::size_t>(d)] != 0 ? 0.0 : uniform(random);
    return x;
  }
};

Eigen::VectorXd multiply(const SpringSystemOperator& a, const Eigen::VectorXd& x,
                         bool isReversed = false) {
  Eigen::VectorXd y = Eigen::VectorXd::Constant(x.size(), std::nan(""));
  for (int p = 0; p < BlockLinearOperator::kParts; ++p) {
    a.multiplyPart(isReversed ? BlockLinearOperator::kParts - 1 - p : p, x.data(), y.data());
  }
  return y;
}

TEST(SpringSystemOperator, IsTheAssembledMatrix) {
  const OperatorCase c;
  const SpringSystemOperator a = c.makeOperator();
  const Eigen::MatrixXd dense = c.assembled();
  const double scale = dense.cwiseAbs().maxCoeff();
  // The parts cover every node once, in order.
  const BlockLinearOperator::PartBounds& bounds = a.partBounds();
  EXPECT_EQ(bounds.front(), 0);
  EXPECT_EQ(bounds.back(), c.block.mesh.nodeCount());
  for (int p = 0; p < BlockLinearOperator::kParts; ++p) EXPECT_LT(bounds[p], bounds[p + 1]) << p;
  for (const unsigned seed : {1u, 2u}) {
    const Eigen::VectorXd x = c.randomDirection(seed);
    const Eigen::VectorXd y = multiply(a, x);
    ASSERT_TRUE(y.allFinite()) << "every row written";
    EXPECT_LT((y - dense * x).cwiseAbs().maxCoeff(), 1e-12 * scale * x.cwiseAbs().sum()) << seed;
  }
  // The preconditioner's blocks, and the shift's scale.
  double largest = 0.0;
  for (Eigen::Index j = 0; j < a.nodeCount(); ++j) {
    const Eigen::Matrix3d expected = dense.block<3, 3>(3 * j, 3 * j);
    EXPECT_LT((a.diagonalBlock(j) - expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "node " << j;
    largest = std::max(largest, expected.diagonal().maxCoeff());
  }
  EXPECT_NEAR(a.largestDiagonalEntry(), largest, 1e-12 * largest);
  // The terms and the volume term matter here (the comparison would fail without either).
  SpringSystemOperator withoutTerms = c.makeOperator();
  withoutTerms.setTerms(nullptr);
  const Eigen::VectorXd x = c.randomDirection(1);
  EXPECT_GT((multiply(withoutTerms, x) - dense * x).cwiseAbs().maxCoeff(), 1.0);
  SpringSystemOperator withoutVolume = c.makeOperator();
  withoutVolume.setVolumeBlocks(nullptr);
  EXPECT_GT((multiply(withoutVolume, x) - dense * x).cwiseAbs().maxCoeff(), 1.0);
}

TEST(SpringSystemOperator, PartsAreIndependentOfOrderAndThreads) {
  const OperatorCase c;
  const SpringSystemOperator a = c.makeOperator();
  const Eigen::VectorXd x = c.randomDirection(5);
  const Eigen::VectorXd expected = multiply(a, x);
  EXPECT_EQ(multiply(a, x, /*isReversed=*/true), expected);
  for (const int threads : {2, 4}) {
    ForkJoinPool pool(threads);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
    runParts(&pool, BlockLinearOperator::kParts,
             [&](int p) { a.multiplyPart(p, x.data(), y.data()); });
    EXPECT_EQ(y, expected) << threads << " threads";
  }
}

// One implicit Euler step of a clamped block pressed by a contact and pulled by gravity, with and
// without the volume term, converged tightly: CG on the matrix-free operator and Cholesky on the
// assembled matrix reach the same state.
TEST(SpringSystemOperator, NewtonWithItMatchesCholesky) {
  for (const double bulkModulus : {0.0, 2e4}) {
    test::BlockSystem block({0.03, 0.03, 0.03}, {3, 3, 3}, SpringLaw::Eesm, false, bulkModulus);
    for (int node = 0; node < 16; ++node) block.system.fixNode(node);  // the z = 0 face
    block.system.gravity_m_s2 = Eigen::Vector3d(0.0, 0.0, -9.81);
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
