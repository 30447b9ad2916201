#include "integrators/PenaltyContacts.h"

#include <Eigen/SVD>
#include <gtest/gtest.h>

namespace tissuesim {
namespace {

// Three nodes of a triangle (joined pairwise) and one contact at an inner point of it.
struct Triangle {
  Eigen::Matrix2Xi edges = (Eigen::Matrix2Xi(2, 3) << 0, 1, 2, 1, 2, 0).finished();
  Eigen::Matrix3Xd x = (Eigen::Matrix3Xd(3, 3) << 0.0, 0.01, 0.0,  //
                        0.0, 0.0, 0.01,                            //
                        0.001, 0.0012, 0.0008).finished();
  PenaltyContactSet set;
  Triangle() {
    PenaltyContact c;
    c.nodes = {0, 1, 2};
    c.weights = {0.5, 0.3, 0.2};
    c.normal = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
    c.offset_m = 0.0005;
    c.stiffness_N_m = 2e4;
    set.add(c);
  }
  double energy(const Eigen::Matrix3Xd& at) const {
    const double delta = std::max(0.0, set.contacts()[0].penetration(at));
    return 0.5 * set.contacts()[0].stiffness_N_m * delta * delta;
  }
};

TEST(PenaltyContacts, ForcesAreTheEnergysNegativeGradientAndStiffnessItsHessian) {
  Triangle t;
  ASSERT_GT(t.set.contacts()[0].penetration(t.x), 0.0);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 3);
  t.set.addForces(t.x, f);
  NodeBlockMatrix k(3, t.edges);
  t.set.addStiffness(t.x, k);
  const Eigen::MatrixXd dense(k.matrix());
  const double h = 1e-8;
  for (int d = 0; d < 9; ++d) {
    Eigen::Matrix3Xd plus = t.x, minus = t.x;
    plus.data()[d] += h;
    minus.data()[d] -= h;
    EXPECT_NEAR(f.data()[d], -(t.energy(plus) - t.energy(minus)) / (2 * h), 1e-6) << d;
    Eigen::Matrix3Xd fPlus = Eigen::Matrix3Xd::Zero(3, 3), fMinus = Eigen::Matrix3Xd::Zero(3, 3);
    t.set.addForces(plus, fPlus);
    t.set.addForces(minus, fMinus);
    const Eigen::VectorXd column = -(fPlus - fMinus).reshaped() / (2 * h);
    EXPECT_LT((dense.col(d) - column).cwiseAbs().maxCoeff(), 1e-6 * 2e4) << d;
  }
  // Action and reaction; the reaction pushes the tool out along the normal.
  const ContactResult reaction = t.set.reaction(t.x, Eigen::Vector3d::Zero());
  EXPECT_LT((f.rowwise().sum() + reaction.toolForce_N).norm(), 1e-12);
  EXPECT_GT(reaction.toolForce_N.dot(t.set.contacts()[0].normal), 0.0);
  EXPECT_EQ(reaction.contactNodes, 1);
  EXPECT_DOUBLE_EQ(reaction.maxPenetration_m, t.set.contacts()[0].penetration(t.x));
}

TEST(PenaltyContacts, AnInactiveContactAddsNothing) {
  Triangle t;
  t.x.row(2).array() -= 0.002;  // the triangle below the plane
  ASSERT_LT(t.set.contacts()[0].penetration(t.x), 0.0);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 3);
  t.set.addForces(t.x, f);
  NodeBlockMatrix k(3, t.edges);
  t.set.addStiffness(t.x, k);
  Eigen::VectorXd nodeStiffness = Eigen::VectorXd::Zero(3);
  t.set.addNodeStiffness(t.x, nodeStiffness);
  EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(k.matrix().coeffs().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(nodeStiffness.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(t.set.reaction(t.x, Eigen::Vector3d::Zero()).contactNodes, 0);
}

TEST(PenaltyContacts, NodeStiffnessBoundsTheRowSums) {
  Triangle t;
  NodeBlockMatrix k(3, t.edges);
  t.set.addStiffness(t.x, k);
  Eigen::VectorXd nodeStiffness = Eigen::VectorXd::Zero(3);
  t.set.addNodeStiffness(t.x, nodeStiffness);
  const Eigen::MatrixXd dense(k.matrix());
  for (int node = 0; node < 3; ++node) {
    // Block Gershgorin, as the explicit integrator's bound uses it: the sum of the spectral
    // norms of the node's blocks.
    double sum = 0.0;
    for (int other = 0; other < 3; ++other) {
      sum += dense.block<3, 3>(3 * node, 3 * other).jacobiSvd().singularValues()[0];
    }
    EXPECT_NEAR(sum, nodeStiffness[node], 1e-9 * sum);
    EXPECT_GT(nodeStiffness[node], 0.0);
  }
}

}  // namespace
}  // namespace tissuesim
