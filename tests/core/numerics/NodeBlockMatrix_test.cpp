#include "numerics/NodeBlockMatrix.h"

#include <stdexcept>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tissuesim
