// SPDX-License-Identifier: Apache-2.0
#include "numerics/BlockConjugateGradient.h"
#include "numerics/NodeBlockMatrix.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/LU>

#include <gtest/gtest.h>
#include <Eigen/IterativeLinearSolvers>

namespace tissuesim {
namespace {

/// A lattice of nx x ny x nz nodes joined to their axis neighbours: a spring network's pattern.
Eigen::Matrix2Xi latticeEdges(int nx, int ny, int nz) {
  std::vector<int> pairs;
  const auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i + 1 < nx) pairs.insert(pairs.end(), {id(i, j, k), id(i + 1, j, k)});
        if (j + 1 < ny) pairs.insert(pairs.end(), {id(i, j, k), id(i, j + 1, k)});
        if (k + 1 < nz) pairs.insert(pairs.end(), {id(i, j, k), id(i, j, k + 1)});
      }
  return Eigen::Map<Eigen::Matrix2Xi>(pairs.data(), 2, static_cast<Eigen::Index>(pairs.size() / 2));
}

/// Random positive semi-definite edge blocks (B B^T, N/m) plus a small mass term on the
/// diagonal: symmetric positive definite, badly enough conditioned to need tens of iterations.
NodeBlockMatrix randomSpdMatrix(const Eigen::Matrix2Xi& edges, int nodes, unsigned seed) {
  NodeBlockMatrix matrix(nodes, edges);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    Eigen::Matrix3d b;
    for (int c = 0; c < 9; ++c) b.data()[c] = uniform(random);
    const Eigen::Matrix3d k = 100.0 * b * b.transpose();
    matrix.addEdgeStiffness(e, k.data());
  }
  for (int i = 0; i < nodes; ++i) matrix.addToDiagonal(i, 0.5 + 0.25 * (1.0 + uniform(random)));
  return matrix;
}

Eigen::VectorXd randomVector(Eigen::Index size, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = uniform(random);
  return v;
}

/// Block-Jacobi preconditioning for Eigen's ConjugateGradient, written independently of
/// BlockConjugateGradient's: every node's 3x3 diagonal block inverted by Eigen's LU.
class EigenBlockJacobi {
 public:
  using Scalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };

  template <typename Matrix>
  EigenBlockJacobi& analyzePattern(const Matrix&) {
    return *this;
  }
  template <typename Matrix>
  EigenBlockJacobi& factorize(const Matrix& a) {
    return compute(a);
  }
  template <typename Matrix>
  EigenBlockJacobi& compute(const Matrix& a) {
    const Eigen::MatrixXd dense(a);
    m_inverses.resize(static_cast<std::size_t>(dense.rows() / 3));
    for (std::size_t j = 0; j < m_inverses.size(); ++j) {
      const auto at = static_cast<Eigen::Index>(3 * j);
      m_inverses[j] = dense.block<3, 3>(at, at).inverse();
    }
    return *this;
  }
  template <typename Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    Eigen::VectorXd z(b.size());
    for (std::size_t j = 0; j < m_inverses.size(); ++j) {
      const auto at = static_cast<Eigen::Index>(3 * j);
      z.segment<3>(at) = m_inverses[j] * b.template segment<3>(at);
    }
    return z;
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  std::vector<Eigen::Matrix3d> m_inverses;
};

TEST(NodeBlockMatrix, BlockProductMatchesTheSparseProduct) {
  const Eigen::Matrix2Xi edges = latticeEdges(5, 4, 3);
  const NodeBlockMatrix a = randomSpdMatrix(edges, 60, 1);
  const Eigen::VectorXd x = randomVector(180, 2);
  Eigen::VectorXd y = Eigen::VectorXd::Constant(180, 7.0);
  a.multiplyNodes(0, 25, x.data(), y.data());
  a.multiplyNodes(25, 60, x.data(), y.data());
  const Eigen::VectorXd expected = a.matrix() * x;
  EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
  const Eigen::Matrix3d block = a.diagonalBlock(7);
  const Eigen::Matrix3d expectedBlock = Eigen::MatrixXd(a.matrix()).block<3, 3>(21, 21);
  EXPECT_EQ(block, expectedBlock);
  EXPECT_NE(block(2, 1), 0.0);  // the off-diagonal entries are compared too
}

TEST(BlockConjugateGradient, SolvesLikeEigensConjugateGradientWithBlockJacobi) {
  const Eigen::Matrix2Xi edges = latticeEdges(8, 6, 5);
  const int nodes = 240;
  NodeBlockMatrix a = randomSpdMatrix(edges, nodes, 3);
  std::vector<char> fixed(3 * nodes, 0);
  for (int d = 0; d < 12; ++d) fixed[static_cast<std::size_t>(d)] = 1;  // clamped DOFs too
  a.applyFixedDofs(fixed);
  Eigen::VectorXd b = randomVector(3 * nodes, 4);
  for (int d = 0; d < 12; ++d) b[d] = 0.0;

  BlockConjugateGradient cg;
  Eigen::VectorXd x;
  const ConjugateGradientReport report = cg.solve(a, b, x, 1e-8, 1000);
  EXPECT_TRUE(report.converged);
  const double residual = (b - a.matrix() * x).norm() / b.norm();
  EXPECT_LE(residual, 1e-8);
  EXPECT_NEAR(report.relativeResidual, residual, 1e-9);  // the recurrence tracks the true one

  // The same method in Eigen: its CG with the 3x3 blocks' inverses as the preconditioner.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                           EigenBlockJacobi>
      eigenCg;
  eigenCg.setTolerance(1e-8);
  eigenCg.compute(a.matrix());
  const Eigen::VectorXd expected = eigenCg.solve(b);
  EXPECT_GT(report.iterations, 10);
  EXPECT_NEAR(report.iterations, static_cast<int>(eigenCg.iterations()), 1);
  EXPECT_LT((x - expected).norm(), 1e-6 * expected.norm());

  // And the point of the blocks: fewer iterations than Eigen's scalar Jacobi preconditioning
  // (on this matrix, whose edge blocks couple the three axes, 118 against 136).
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> scalarCg;
  scalarCg.setTolerance(1e-8);
  scalarCg.compute(a.matrix());
  const Eigen::VectorXd scalarSolution = scalarCg.solve(b);
  EXPECT_LT((scalarSolution - expected).norm(), 1e-6 * expected.norm());
  EXPECT_LT(report.iterations, static_cast<int>(scalarCg.iterations()));
}

/// Adds k u u^T to the matrix (its nodes, three or four, must be joined by edges) and returns it
/// as a term (a triangle's leaves the fourth slot empty, as PenaltyContacts does).
RankOneTerm addRankOneTerm(NodeBlockMatrix& a, const std::vector<int>& nodes,
                           const std::vector<double>& weights, const Eigen::Vector3d& normal,
                           double stiffness) {
  RankOneTerm term;
  term.stiffness_N_m = stiffness;
  for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
    term.nodes[i] = i < nodes.size() ? nodes[i] : nodes[0];
    term.blocks[i] = (i < nodes.size() ? weights[i] : 0.0) * normal.normalized();
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      a.addBlock(nodes[i], nodes[j], stiffness * term.blocks[i] * term.blocks[j].transpose());
    }
  }
  return term;
}

// A matrix that is its block diagonal plus rank-one terms, two of them sharing two nodes, a
// tet's over four nodes sharing three with those, and one on a node with a fixed DOF: the
// preconditioner is then the matrix itself, and CG given the terms converges in one product;
// without them, block Jacobi takes several.
TEST(BlockConjugateGradient, RankOneTermsAreInvertedExactly) {
  // Triangles (0, 1, 2), (1, 2, 3), (4, 5, 6), and the tet (0, 1, 2, 3), joined pairwise.
  const Eigen::Matrix2Xi edges = (Eigen::Matrix2Xi(2, 9) << 0, 0, 1, 1, 2, 4, 4, 5, 0,  //
                                  1, 2, 2, 3, 3, 5, 6, 6, 3)
                                     .finished();
  NodeBlockMatrix a(7, edges);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < 7; ++i) {
    Eigen::Matrix3d m;
    for (int c = 0; c < 9; ++c) m.data()[c] = uniform(random);
    a.addBlock(i, i, m * m.transpose() + Eigen::Matrix3d::Identity());
  }
  std::vector<RankOneTerm> terms;
  terms.push_back(addRankOneTerm(a, {0, 1, 2}, {0.5, 0.3, 0.2}, {0.1, 1.0, 0.2}, 1e4));
  terms.push_back(addRankOneTerm(a, {1, 2, 3}, {0.2, 0.2, 0.6}, {-0.3, 1.0, 0.1}, 2e4));
  terms.push_back(addRankOneTerm(a, {4, 5, 6}, {0.1, 0.8, 0.1}, {0.0, 0.2, 1.0}, 5e3));
  terms.push_back(addRankOneTerm(a, {3, 0, 1, 2}, {0.4, 0.1, 0.2, 0.3}, {0.5, -0.2, 1.0}, 3e4));
  std::vector<char> fixed(21, 0);
  fixed[3 * 5 + 2] = 1;  // node 5's z: the term's u is zero there, as PenaltyContacts makes it
  terms[2].blocks[1][2] = 0.0;
  a.applyFixedDofs(fixed);
  Eigen::VectorXd b = randomVector(21, 12);
  b[3 * 5 + 2] = 0.0;

  BlockConjugateGradient cg;
  Eigen::VectorXd x;
  const ConjugateGradientReport exact = cg.solve(a, b, x, 1e-10, 100, terms);
  EXPECT_EQ(exact.iterations, 1);
  EXPECT_TRUE(exact.converged);
  EXPECT_LT((a.matrix() * x - b).norm(), 1e-10 * b.norm());

  Eigen::VectorXd plain;
  const ConjugateGradientReport blockJacobi = cg.solve(a, b, plain, 1e-10, 100);
  EXPECT_GT(blockJacobi.iterations, 3);
  EXPECT_LT((plain - x).norm(), 1e-8 * x.norm());
  // The scratch is cleared after a solve: the plain solve above saw no terms, and a repeat
  // with them is exact again.
  EXPECT_EQ(cg.solve(a, b, x, 1e-10, 100, terms).iterations, 1);

  // A term the preconditioner cannot take (no stiffness, a NaN) leaves it plain block Jacobi:
  // the same iterations and solution as without terms.
  for (const double bad : {0.0, std::nan("")}) {
    std::vector<RankOneTerm> unusable = terms;
    unusable[1].stiffness_N_m = bad;
    Eigen::VectorXd y;
    const ConjugateGradientReport report = cg.solve(a, b, y, 1e-10, 100, unusable);
    EXPECT_EQ(report.iterations, blockJacobi.iterations) << bad;
    EXPECT_EQ(y, plain) << bad;
  }
}

// On a spring-like matrix with stiff contacts the terms save products and change nothing else.
TEST(BlockConjugateGradient, RankOneTermsSaveIterationsOnANetwork) {
  // A 6 x 5 x 4 lattice plus the diagonals of its bottom layer's squares (its "surface"
  // triangles' third edges).
  Eigen::Matrix2Xi lattice = latticeEdges(6, 5, 4);
  std::vector<int> pairs(lattice.data(), lattice.data() + lattice.size());
  for (int j = 0; j + 1 < 5; ++j)
    for (int i = 0; i + 1 < 6; ++i) pairs.insert(pairs.end(), {i + 6 * j, i + 1 + 6 * (j + 1)});
  const Eigen::Matrix2Xi edges =
      Eigen::Map<Eigen::Matrix2Xi>(pairs.data(), 2, static_cast<Eigen::Index>(pairs.size() / 2));
  NodeBlockMatrix a = randomSpdMatrix(edges, 120, 13);
  std::vector<RankOneTerm> terms;
  for (int i = 0; i < 4; ++i) {
    // Triangles (i, i + 1, i + 7) on the bottom layer, neighbours sharing an edge's node.
    terms.push_back(addRankOneTerm(a, {i, i + 1, i + 7}, {0.3, 0.3, 0.4}, {0.1, 0.1, -1.0}, 1e5));
  }
  const Eigen::VectorXd b = randomVector(360, 14);
  BlockConjugateGradient cg;
  Eigen::VectorXd withTerms, without;
  const ConjugateGradientReport exact = cg.solve(a, b, withTerms, 1e-10, 2000, terms);
  const ConjugateGradientReport plain = cg.solve(a, b, without, 1e-10, 2000);
  ASSERT_TRUE(exact.converged);
  ASSERT_TRUE(plain.converged);
  EXPECT_LT(exact.iterations, plain.iterations);
  EXPECT_LT((withTerms - without).norm(), 1e-8 * without.norm());
  EXPECT_LT((a.matrix() * withTerms - b).norm(), 1e-9 * b.norm());
}

TEST(BlockConjugateGradient, ResultsDoNotDependOnTheThreadCount) {
  const Eigen::Matrix2Xi edges = latticeEdges(10, 7, 6);
  const int nodes = 420;
  const NodeBlockMatrix a = randomSpdMatrix(edges, nodes, 5);
  const Eigen::VectorXd b = randomVector(3 * nodes, 6);
  BlockConjugateGradient serial;
  Eigen::VectorXd expected;
  const ConjugateGradientReport expectedReport = serial.solve(a, b, expected, 1e-10, 2000);
  ASSERT_TRUE(expectedReport.converged);
  for (const int threads : {2, 4}) {
    ForkJoinPool pool(threads);
    BlockConjugateGradient parallel;
    parallel.setThreadPool(&pool);
    Eigen::VectorXd x;
    for (int repeat = 0; repeat < 2; ++repeat) {  // the scratch is reused between solves
      const ConjugateGradientReport report = parallel.solve(a, b, x, 1e-10, 2000);
      EXPECT_EQ(report.iterations, expectedReport.iterations) << threads << " threads";
      EXPECT_EQ((x - expected).cwiseAbs().maxCoeff(), 0.0) << threads << " threads";
    }
  }
}

TEST(BlockConjugateGradient, ReportsAnUnconvergedSolve) {
  const Eigen::Matrix2Xi edges = latticeEdges(6, 5, 4);
  const NodeBlockMatrix a = randomSpdMatrix(edges, 120, 7);
  const Eigen::VectorXd b = randomVector(360, 8);
  BlockConjugateGradient cg;
  Eigen::VectorXd x;
  const ConjugateGradientReport capped = cg.solve(a, b, x, 1e-10, 3);
  EXPECT_EQ(capped.iterations, 3);
  EXPECT_FALSE(capped.converged);
  EXPECT_GT(capped.relativeResidual, 1e-10);
  EXPECT_NEAR(capped.relativeResidual, (b - a.matrix() * x).norm() / b.norm(), 1e-9);

  // Negative definite: no positive curvature along the first direction.
  NodeBlockMatrix negative(120, edges);
  for (int i = 0; i < 120; ++i) negative.addToDiagonal(i, -1.0);
  const ConjugateGradientReport indefinite = cg.solve(negative, b, x, 1e-10, 100);
  EXPECT_FALSE(indefinite.converged);
  EXPECT_TRUE(x.allFinite());
}

TEST(BlockConjugateGradient, AWarmStartNearTheAnswerSavesIterations) {
  const Eigen::Matrix2Xi edges = latticeEdges(8, 6, 5);
  const int nodes = 240;
  const NodeBlockMatrix a = randomSpdMatrix(edges, nodes, 11);
  const Eigen::VectorXd b = randomVector(3 * nodes, 12);
  BlockConjugateGradient cg;
  Eigen::VectorXd cold;
  const ConjugateGradientReport coldReport = cg.solve(a, b, cold, 1e-8, 2000);
  ASSERT_TRUE(coldReport.converged);
  ASSERT_GT(coldReport.iterations, 20);
  // From the answer itself: nothing to do.
  Eigen::VectorXd x = cold;
  const ConjugateGradientReport atAnswer = cg.solve(a, b, x, 1e-6, 2000, {}, true);
  EXPECT_TRUE(atAnswer.converged);
  EXPECT_EQ(atAnswer.iterations, 0);
  EXPECT_EQ(x, cold);
  // From 1 % off it (the next time step's Newton step, about): the same answer, in fewer
  // products; and the same guess ignored without isWarm.
  const Eigen::VectorXd guess =
      cold + 0.01 * cold.norm() / std::sqrt(3.0 * nodes) * randomVector(3 * nodes, 13);
  x = guess;
  const ConjugateGradientReport warm = cg.solve(a, b, x, 1e-8, 2000, {}, true);
  EXPECT_TRUE(warm.converged);
  EXPECT_LT(warm.iterations, coldReport.iterations);
  EXPECT_LT((a.matrix() * x - b).norm(), 1e-8 * b.norm() * (1.0 + 1e-9));
  x = guess;
  EXPECT_EQ(cg.solve(a, b, x, 1e-8, 2000).iterations, coldReport.iterations);
  EXPECT_EQ(x, cold);
  // A guess with a NaN in it is not taken.
  x = guess;
  x[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(cg.solve(a, b, x, 1e-8, 2000, {}, true).iterations, coldReport.iterations);
}

TEST(BlockConjugateGradient, ZeroRightHandSideGivesZero) {
  const Eigen::Matrix2Xi edges = latticeEdges(3, 3, 3);
  const NodeBlockMatrix a = randomSpdMatrix(edges, 27, 9);
  BlockConjugateGradient cg;
  Eigen::VectorXd x = Eigen::VectorXd::Ones(81);
  const ConjugateGradientReport report = cg.solve(a, Eigen::VectorXd::Zero(81), x, 1e-8, 100);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.iterations, 0);
  EXPECT_EQ(x.cwiseAbs().maxCoeff(), 0.0);
  x.setOnes();  // a warm start's guess is no answer to b = 0 either
  EXPECT_EQ(cg.solve(a, Eigen::VectorXd::Zero(81), x, 1e-8, 100, {}, true).iterations, 0);
  EXPECT_EQ(x.cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace tissuesim
