// SPDX-License-Identifier: Apache-2.0
// A stiffness by node rows: each node's neighbours through its cells, and the product, diagonal
// blocks and assembly of the current slot against the dense matrix the same blocks make.

#include "fem/NodeRowStiffness.h"

#include <random>

#include <gtest/gtest.h>

#include "numerics/NodeBlockMatrix.h"
#include "support/TestMeshes.h"

namespace tissuesim {
namespace {

TEST(NodeRowStiffness, TheNeighboursThroughTetsAreTheStars) {
  const TetMesh mesh = test::unstructuredBlock();
  std::vector<int> start{0};
  std::vector<int> nodes;
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    for (int a = 0; a < 4; ++a) nodes.push_back(mesh.tets(a, t));
    start.push_back(static_cast<int>(nodes.size()));
  }
  const NodeStars rows = cellNeighbours(start, nodes, mesh.nodeCount());
  const NodeStars stars = nodeStars(mesh.tets, nodeTetIncidence(mesh.tets, mesh.nodeCount()));
  EXPECT_EQ(rows.start, stars.start);
  EXPECT_EQ(rows.nodes, stars.nodes);
}

TEST(NodeRowStiffness, ANodeInNoCellNeighboursItselfAlone) {
  // Cells {0, 2, 3} and {3, 4}: node 1 is in none.
  const NodeStars rows = cellNeighbours({0, 3, 5}, {0, 2, 3, 3, 4}, 5);
  EXPECT_EQ(rows.start, (std::vector<int>{0, 3, 4, 7, 11, 13}));
  EXPECT_EQ(rows.nodes, (std::vector<int>{0, 2, 3, 1, 0, 2, 3, 0, 2, 3, 4, 3, 4}));
}

TEST(NodeRowStiffness, ProductsBlocksAndAssemblyAreTheCurrentSlotsMatrix) {
  const NodeStars neighbours = cellNeighbours({0, 4, 7}, {0, 1, 2, 4, 2, 3, 4}, 5);
  const NodeRowStiffness rows(neighbours);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // The trial slot filled, then made current; the other slot holds something else.
  NodeRowStiffness::Blocks& trial = rows.slot(StiffnessSlot::Trial);
  rows.slot(StiffnessSlot::Current).setConstant(1e6);
  for (Eigen::Index e = 0; e < trial.cols(); ++e) {
    for (int i = 0; i < 9; ++i) trial(i, e) = u(random);
  }
  rows.acceptTrial();
  const Eigen::Index n = 5;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  Eigen::Matrix2Xi pairs(2, 0);
  for (int j = 0; j < n; ++j) {
    for (int e = neighbours.start[static_cast<std::size_t>(j)];
         e < neighbours.start[static_cast<std::size_t>(j) + 1]; ++e) {
      const int m = neighbours.nodes[static_cast<std::size_t>(e)];
      dense.block<3, 3>(3 * j, 3 * m) = Eigen::Map<const Eigen::Matrix3d>(trial.col(e).data());
      if (m > j) {
        pairs.conservativeResize(2, pairs.cols() + 1);
        pairs.col(pairs.cols() - 1) << j, m;
      }
    }
  }
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(3 * n, -1.0, 2.0);
  Eigen::VectorXd y = Eigen::VectorXd::Ones(3 * n);
  rows.addProduct(0, 2, x.data(), y.data());
  rows.addProduct(2, n, x.data(), y.data());
  EXPECT_LT((y - Eigen::VectorXd::Ones(3 * n) - dense * x).norm(), 1e-12);
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::Matrix3d block = Eigen::Matrix3d::Identity();
    rows.addDiagonalBlock(j, block);
    const Eigen::Matrix3d expected = Eigen::Matrix3d::Identity() + dense.block<3, 3>(3 * j, 3 * j);
    EXPECT_LT((block - expected).norm(), 1e-15) << j;
  }
  NodeBlockMatrix matrix(n, pairs);
  rows.addStiffness(matrix);
  EXPECT_LT((Eigen::MatrixXd(matrix.matrix()) - dense).norm(), 1e-12);
  std::vector<Eigen::Index> work(static_cast<std::size_t>(n), 0);
  rows.addProductWork(work);
  EXPECT_EQ(work, (std::vector<Eigen::Index>{36, 36, 45, 27, 45}));
}

}  // namespace
}  // namespace tissuesim
