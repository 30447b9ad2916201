// SPDX-License-Identifier: Apache-2.0
#include "numerics/NodeBlockMatrix.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "numerics/CpuFeatures.h"

namespace tissuesim {
namespace {

TEST(NodeBlockMatrix, AssemblesLikeADenseMatrix) {
  Eigen::Matrix2Xi edges(2, 3);
  edges << 0, 1, 3, 1, 2, 0;  // (0,1), (1,2), (3,0)
  NodeBlockMatrix matrix(4, edges);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(12, 12);
  Eigen::Matrix3d k;
  k << 4, 1, 0, 1, 3, 2, 0, 2, 5;
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    const Eigen::Matrix3d ke = (e + 1.0) * k;
    matrix.addEdgeStiffness(edges(0, e), edges(1, e), ke);
    const int a = edges(0, e), b = edges(1, e);
    dense.block<3, 3>(3 * a, 3 * a) += ke;
    dense.block<3, 3>(3 * b, 3 * b) += ke;
    dense.block<3, 3>(3 * a, 3 * b) -= ke;
    dense.block<3, 3>(3 * b, 3 * a) -= ke;
  }
  for (int i = 0; i < 4; ++i) {
    matrix.addToDiagonal(i, 10.0 + i);
    dense.block<3, 3>(3 * i, 3 * i).diagonal().array() += 10.0 + i;
  }
  EXPECT_LT((Eigen::MatrixXd(matrix.matrix()) - dense).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(matrix.matrix().nonZeros(), 9 * (4 + 2 * 3));
  EXPECT_THROW(matrix.addBlock(2, 3, k), std::logic_error);  // no edge (2, 3)

  std::vector<char> fixed(12, 0);
  fixed[4] = 1;  // node 1, y
  matrix.applyFixedDofs(fixed);
  const Eigen::MatrixXd applied(matrix.matrix());
  for (int j = 0; j < 12; ++j) {
    EXPECT_EQ(applied(4, j), j == 4 ? 1.0 : 0.0);
    EXPECT_EQ(applied(j, 4), j == 4 ? 1.0 : 0.0);
  }
  EXPECT_EQ(applied(0, 0), dense(0, 0));
}

TEST(NodeBlockMatrix, BothProductKernelsMatchTheSparseProduct) {
  // A chain of 40 nodes (rows of 2 and 3 neighbours: odd and even 3 n_j, so every tail of the
  // SIMD loops is taken) and a hub joined to 100 of 120 nodes (past the gather buffer: the
  // plain loop). Off-diagonal blocks are general, (i, j) = B and (j, i) = B^T, so a kernel that
  // read a block the wrong way round would fail.
  const int nodes = 121;
  std::vector<int> pairs;
  for (int i = 0; i + 1 < 40; ++i) pairs.insert(pairs.end(), {i, i + 1});
  for (int i = 0; i < 100; ++i) pairs.insert(pairs.end(), {120, i + 20});
  const Eigen::Matrix2Xi edges =
      Eigen::Map<Eigen::Matrix2Xi>(pairs.data(), 2, static_cast<Eigen::Index>(pairs.size() / 2));
  NodeBlockMatrix matrix(nodes, edges);
  std::srand(3);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    const Eigen::Matrix3d b = Eigen::Matrix3d::Random();
    matrix.addBlock(edges(0, e), edges(1, e), b);
    matrix.addBlock(edges(1, e), edges(0, e), b.transpose());
  }
  for (int i = 0; i < nodes; ++i) {
    const Eigen::Matrix3d d = Eigen::Matrix3d::Random();
    matrix.addBlock(i, i, d + d.transpose());
  }
  const Eigen::VectorXd x = Eigen::VectorXd::Random(3 * nodes);
  const Eigen::VectorXd expected = matrix.matrix() * x;
  const double tolerance = 1e-13 * expected.cwiseAbs().maxCoeff();
  const auto check = [&](auto kernel, const char* name) {
    Eigen::VectorXd y = Eigen::VectorXd::Constant(3 * nodes, 7.0);
    kernel(matrix.rows(), 0, 57, x.data(), y.data());
    kernel(matrix.rows(), 57, nodes, x.data(), y.data());
    EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), tolerance) << name;
  };
  check(multiplyNodeRowsSse2, "SSE2");
  if (hasAvxAndFma()) check(multiplyNodeRowsAvxFma, "AVX+FMA");
  Eigen::VectorXd y(3 * nodes);
  matrix.multiplyNodes(0, nodes, x.data(), y.data());
  EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), tolerance);
}

TEST(NodeBlockMatrix, EdgeIndexedAssemblyMatchesTheSearchedOne) {
  Eigen::Matrix2Xi edges(2, 4);
  edges << 0, 2, 3, 1, 1, 1, 0, 3;  // (0,1), (2,1), (3,0), (1,3): both orders of node pairs
  NodeBlockMatrix byNodes(4, edges);
  NodeBlockMatrix byEdge(4, edges);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    Eigen::Matrix3d k;
    k << 1, 2, 3, 4, 5, 6, 7, 8, 9;  // not symmetric: a transposed block would show
    k *= e + 1.0;
    byNodes.addEdgeStiffness(edges(0, e), edges(1, e), k);
    byEdge.addEdgeStiffness(e, k.data());
  }
  EXPECT_EQ(
      (Eigen::MatrixXd(byNodes.matrix()) - Eigen::MatrixXd(byEdge.matrix())).cwiseAbs().maxCoeff(),
      0.0);
  EXPECT_NE(Eigen::MatrixXd(byEdge.matrix()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(NodeBlockMatrix, AssignedStiffnessEqualsClearedAndAdded) {
  // Both orders of node pairs, a node with no edges, and blocks that are not symmetric (a
  // transposed block would show). Repeated edges take the adding path.
  for (const bool isRepeated : {false, true}) {
    Eigen::Matrix2Xi edges(2, isRepeated ? 5 : 4);
    if (isRepeated) {
      edges << 0, 2, 3, 1, 1, 1, 1, 0, 3, 0;
    } else {
      edges << 0, 2, 3, 1, 1, 1, 0, 3;
    }
    Eigen::Matrix<double, 9, Eigen::Dynamic> blocks(9, edges.cols());
    for (Eigen::Index e = 0; e < edges.cols(); ++e) {
      for (int v = 0; v < 9; ++v) blocks(v, e) = (e + 1.0) * (v + 1.0) + 0.1 * v * v;
    }
    NodeBlockMatrix added(5, edges);
    for (Eigen::Index e = 0; e < edges.cols(); ++e) added.addEdgeStiffness(e, blocks.col(e).data());
    NodeBlockMatrix assigned(5, edges);
    for (int i = 0; i < 5; ++i) assigned.addToDiagonal(i, 1e3);  // stale values to overwrite
    assigned.assignEdgeStiffness(blocks * 3.0);
    assigned.assignEdgeStiffness(blocks);
    const Eigen::MatrixXd expected(added.matrix());
    EXPECT_LT((Eigen::MatrixXd(assigned.matrix()) - expected).cwiseAbs().maxCoeff(),
              1e-13 * expected.cwiseAbs().maxCoeff())
        << (isRepeated ? "repeated edges" : "unique edges");
    EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.0);
  }
  NodeBlockMatrix matrix(2, (Eigen::Matrix2Xi(2, 1) << 0, 1).finished());
  EXPECT_THROW(matrix.assignEdgeStiffness(Eigen::Matrix<double, 9, Eigen::Dynamic>(9, 2)),
               std::invalid_argument);
}

TEST(NodeBlockMatrix, EdgesPastTheBlocksGivenAreZero) {
  // The pattern's last edges (a volume cell's extra pairs) get no block from the springs: an
  // assignment zeroes them, stale values included, and leaves the diagonal to the given ones.
  Eigen::Matrix2Xi edges(2, 4);
  edges << 0, 1, 2, 0, 1, 2, 3, 3;
  Eigen::Matrix<double, 9, Eigen::Dynamic> blocks(9, 2);
  for (Eigen::Index e = 0; e < 2; ++e) {
    for (int v = 0; v < 9; ++v) blocks(v, e) = (e + 1.0) * (v + 2.0);
  }
  NodeBlockMatrix added(4, edges);
  for (Eigen::Index e = 0; e < 2; ++e) added.addEdgeStiffness(e, blocks.col(e).data());
  NodeBlockMatrix assigned(4, edges);
  Eigen::Matrix<double, 9, Eigen::Dynamic> stale =
      Eigen::Matrix<double, 9, Eigen::Dynamic>::Ones(9, 4);
  assigned.assignEdgeStiffness(stale);
  assigned.assignEdgeStiffness(blocks);
  const Eigen::MatrixXd expected(added.matrix());
  EXPECT_EQ((Eigen::MatrixXd(assigned.matrix()) - expected).cwiseAbs().maxCoeff(), 0.0);
  const Eigen::MatrixXd dense(assigned.matrix());
  EXPECT_EQ(dense.block(9, 6, 3, 3).cwiseAbs().maxCoeff(), 0.0) << "edge (2, 3) has no block";
  EXPECT_GT(dense.block(3, 0, 3, 3).cwiseAbs().maxCoeff(), 0.0);
}

TEST(NodeBlockMatrix, ResultsDoNotDependOnTheThreadCount) {
  // The assignment on a pool writes every node's columns once, whichever thread runs its range:
  // the matrix is bit-identical to the serial one, stale values included.
  constexpr int kNodes = 300;
  Eigen::Matrix2Xi edges(2, 3 * (kNodes - 7));
  for (int i = 0; i + 7 < kNodes; ++i) edges.middleCols<3>(3 * i) << i, i, i, i + 1, i + 3, i + 7;
  Eigen::Matrix<double, 9, Eigen::Dynamic> blocks(9, edges.cols());
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    for (int v = 0; v < 9; ++v)
      blocks(v, e) = std::sin(0.37 * static_cast<double>(e) + v) + 0.01 * v;
  }
  NodeBlockMatrix serial(kNodes, edges);
  serial.assignEdgeStiffness(blocks);
  for (const int threads : {2, 3}) {
    ForkJoinPool pool(threads);
    NodeBlockMatrix parallel(kNodes, edges);
    for (int i = 0; i < kNodes; ++i) parallel.addToDiagonal(i, 1e3);  // stale values to overwrite
    parallel.assignEdgeStiffness(blocks * 2.0, &pool);
    parallel.assignEdgeStiffness(blocks, &pool);
    const Eigen::Map<const Eigen::VectorXd> expected(serial.matrix().valuePtr(),
                                                     serial.matrix().nonZeros());
    const Eigen::Map<const Eigen::VectorXd> actual(parallel.matrix().valuePtr(),
                                                   parallel.matrix().nonZeros());
    EXPECT_EQ(actual, expected) << threads << " threads";
  }
}

TEST(NodeBlockMatrix, FixedDofsFollowChangedFlags) {
  Eigen::Matrix2Xi edges(2, 2);
  edges << 0, 1, 1, 2;
  NodeBlockMatrix matrix(3, edges);
  const auto fill = [&] {
    matrix.setZero();
    for (Eigen::Index e = 0; e < edges.cols(); ++e) {
      matrix.addEdgeStiffness(e, Eigen::Matrix3d::Constant(2.0).eval().data());
    }
  };
  std::vector<char> fixed(9, 0);
  fixed[0] = 1;
  fill();
  matrix.applyFixedDofs(fixed);
  EXPECT_EQ(Eigen::MatrixXd(matrix.matrix())(0, 3), 0.0);
  EXPECT_EQ(Eigen::MatrixXd(matrix.matrix())(8, 5), -2.0);
  // Other flags on the next call: the listed entries must follow them, not the first set.
  fixed[0] = 0;
  fixed[8] = 1;
  fill();
  matrix.applyFixedDofs(fixed);
  const Eigen::MatrixXd applied(matrix.matrix());
  EXPECT_EQ(applied(0, 3), -2.0);
  EXPECT_EQ(applied(0, 0), 2.0);
  EXPECT_EQ(applied(8, 5), 0.0);
  EXPECT_EQ(applied(5, 8), 0.0);
  EXPECT_EQ(applied(8, 8), 1.0);
}

}  // namespace
}  // namespace tissuesim
