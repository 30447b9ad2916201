// SPDX-License-Identifier: Apache-2.0
#include "forces/PenaltyContacts.h"

#include <gtest/gtest.h>
#include <Eigen/SVD>

namespace tissuesim {
namespace {

// Three nodes of a triangle (joined pairwise) and one contact at an inner point of it.
struct Triangle {
  Eigen::Matrix2Xi edges = (Eigen::Matrix2Xi(2, 3) << 0, 1, 2, 1, 2, 0).finished();
  Eigen::Matrix3Xd x = (Eigen::Matrix3Xd(3, 3) << 0.0, 0.01, 0.0,  //
                        0.0, 0.0, 0.01,                            //
                        0.001, 0.0012, 0.0008)
                           .finished();
  PenaltyContactSet set;
  Triangle() {
    PenaltyContact c;
    c.nodes = {0, 1, 2, 0};
    c.weights = {0.5, 0.3, 0.2, 0.0};
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

TEST(PenaltyContacts, RankOneTermsAreTheStiffnessLessTheFixedDofs) {
  Triangle t;
  PenaltyContact below = t.set.contacts()[0];
  below.offset_m = 1.0;  // inactive: left out of both
  t.set.add(below);
  std::vector<char> fixed(9, 0);
  fixed[4] = 1;  // node 1's y
  NodeBlockMatrix k(3, t.edges);
  t.set.addStiffness(t.x, k);
  k.applyFixedDofs(fixed);
  std::vector<RankOneTerm> terms(5);  // stale entries are overwritten
  t.set.rankOneTerms(t.x, fixed, terms);
  ASSERT_EQ(terms.size(), 1u);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(9);
  for (std::size_t i = 0; i < kMaxTermNodes; ++i)
    u.segment<3>(3 * terms[0].nodes[i]) += terms[0].blocks[i];
  EXPECT_EQ(u[4], 0.0);
  Eigen::MatrixXd expected = terms[0].stiffness_N_m * u * u.transpose();
  expected(4, 4) = 1.0;  // applyFixedDofs' identity
  EXPECT_LT((Eigen::MatrixXd(k.matrix()) - expected).cwiseAbs().maxCoeff(), 1e-12 * 2e4);
}

TEST(PenaltyContacts, ASupportPushesTheTissueButNotTheInstrumentAndComesAfterIt) {
  // The tray's contact (a support) and the instrument's, on the same triangle, both pressed: the
  // tissue feels both, the instrument only its own; the instrument's term comes first and is
  // counted as the one to invert exactly.
  Triangle t;
  PenaltyContact support = t.set.contacts()[0];
  support.normal = Eigen::Vector3d(0.0, 0.0, -1.0);
  support.offset_m = -0.0015;  // the tray at z = 1.5 mm: the point (z about 1 mm) is below it
  support.stiffness_N_m = 5e3;
  support.isSupport = true;
  PenaltyContactSet set;
  set.add(support);  // added first: the terms still put the instrument's first
  set.add(t.set.contacts()[0]);
  ASSERT_GT(support.penetration(t.x), 0.0);

  const ContactResult onTool = set.reaction(t.x, Eigen::Vector3d::Zero());
  const ContactResult instrumentOnly = t.set.reaction(t.x, Eigen::Vector3d::Zero());
  EXPECT_EQ(onTool.contactNodes, 1);
  EXPECT_TRUE(onTool.toolForce_N.isApprox(instrumentOnly.toolForce_N));

  Eigen::Matrix3Xd both = Eigen::Matrix3Xd::Zero(3, 3);
  set.addForces(t.x, both);
  Eigen::Matrix3Xd instrument = Eigen::Matrix3Xd::Zero(3, 3);
  t.set.addForces(t.x, instrument);
  const Eigen::Vector3d trayPush = (both - instrument).rowwise().sum();
  EXPECT_NEAR(trayPush.z(), support.stiffness_N_m * support.penetration(t.x), 1e-12);
  EXPECT_NEAR(trayPush.head<2>().norm(), 0.0, 1e-12);

  std::vector<RankOneTerm> terms;
  EXPECT_EQ(set.rankOneTerms(t.x, std::vector<char>(9, 0), terms), 1u);
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_EQ(terms[0].stiffness_N_m, t.set.contacts()[0].stiffness_N_m);
  EXPECT_EQ(terms[1].stiffness_N_m, support.stiffness_N_m);
}

TEST(PenaltyContacts, AnInactiveContactAddsNothing) {
  Triangle t;
  t.x.row(2).array() -= 0.002;  // the triangle below the plane
  ASSERT_LT(t.set.contacts()[0].penetration(t.x), 0.0);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 3);
  t.set.addForces(t.x, f);
  NodeBlockMatrix k(3, t.edges);
  t.set.addStiffness(t.x, k);
  EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(k.matrix().coeffs().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(t.set.reaction(t.x, Eigen::Vector3d::Zero()).contactNodes, 0);
  std::vector<RankOneTerm> terms;
  t.set.rankOneTerms(t.x, std::vector<char>(9, 0), terms);
  EXPECT_TRUE(terms.empty());
}

/// One free node (2 g) in one contact, moving into the tissue: the explicit integrator's impulse.
struct NodeInContact {
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 1);
  Eigen::Matrix3Xd v = (Eigen::Matrix3Xd(3, 1) << 0.01, 0.0, 0.05).finished();
  Eigen::VectorXd mass = Eigen::VectorXd::Constant(1, 0.002);
  std::vector<char> fixed = std::vector<char>(3, 0);
  PenaltyContactSet set;
  NodeInContact(double stiffness, double damping, double offset) {
    PenaltyContact c;
    c.nodes = {0, 0, 0, 0};
    c.weights = {1.0, 0.0, 0.0, 0.0};
    c.normal = Eigen::Vector3d::UnitZ();
    c.offset_m = offset;
    c.stiffness_N_m = stiffness;
    c.damping_N_s_m = damping;
    set.add(c);
  }
};

TEST(PenaltyContacts, ImpulsesAreBackwardEulerOfTheContactAlone) {
  const double h = 2e-4, k = 1e4, c = 6.0;
  NodeInContact node(k, c, -0.0001);  // 0.1 mm in, moving further in at 5 cm/s
  const Eigen::Vector3d onTool = node.set.applyImpulses(node.x, node.mass, node.fixed, h, node.v);
  // m (u' - u) = -h (k (delta + h u') + c u')
  const double m = 0.002, u = 0.05, delta = 0.0001;
  EXPECT_NEAR(node.v(2, 0), (m * u - h * k * delta) / (m + h * h * k + h * c), 1e-15);
  EXPECT_EQ(node.v(0, 0), 0.01);  // tangential: untouched
  // The tool gets what the node lost: m (u - u') along the normal.
  EXPECT_NEAR(onTool.z(), m * (u - node.v(2, 0)), 1e-15);
  EXPECT_EQ(onTool.head<2>(), Eigen::Vector2d::Zero());
  // A support's impulse is not the tool's.
  NodeInContact onTray(k, c, -0.0001);
  PenaltyContact support = onTray.set.contacts()[0];
  support.isSupport = true;
  onTray.set.clear();
  onTray.set.add(support);
  EXPECT_EQ(onTray.set.applyImpulses(onTray.x, onTray.mass, onTray.fixed, h, onTray.v),
            Eigen::Vector3d::Zero());
  EXPECT_LT(onTray.v(2, 0), u);  // though it pushed the node

  // Stiff beyond any explicit bound (h^2 k / m = 2e4): bounded, it stops the node and takes the
  // penetration out within the step.
  NodeInContact stiff(1e12, 0.0, -0.0001);
  stiff.set.applyImpulses(stiff.x, stiff.mass, stiff.fixed, h, stiff.v);
  EXPECT_NEAR(stiff.v(2, 0), -delta / h, 1e-6);

  // Leaving the contact: no pull.
  NodeInContact leaving(k, c, 0.001);  // 1 mm clear of the plane
  leaving.v(2, 0) = -0.05;
  leaving.set.applyImpulses(leaving.x, leaving.mass, leaving.fixed, h, leaving.v);
  EXPECT_EQ(leaving.v(2, 0), -0.05);

  // A held node does not move.
  NodeInContact held(k, c, -0.0001);
  held.fixed[1] = 1;
  held.set.applyImpulses(held.x, held.mass, held.fixed, h, held.v);
  EXPECT_EQ(held.v(2, 0), 0.05);
}

TEST(PenaltyContacts, ATethersForceIsFeltAndItsStretchIsNoPenetration) {
  // A grasp's spring (Grasp.h) pulls the node 2 mm back towards its target: the tool feels
  // k delta, and reports no penetration and no contact point.
  NodeInContact node(2000.0, 0.0, -0.002);
  PenaltyContact tether = node.set.contacts()[0];
  tether.isTether = true;
  node.set.clear();
  node.set.add(tether);
  const ContactResult felt = node.set.reaction(node.x, Eigen::Vector3d::Zero());
  EXPECT_NEAR(felt.toolForce_N.z(), 2000.0 * 0.002, 1e-12);
  EXPECT_EQ(felt.maxPenetration_m, 0.0);
  EXPECT_EQ(felt.contactNodes, 0);
  tether.isTether = false;  // the check can fail: as a contact it is 2 mm deep
  node.set.clear();
  node.set.add(tether);
  EXPECT_NEAR(node.set.reaction(node.x, Eigen::Vector3d::Zero()).maxPenetration_m, 0.002, 1e-15);
}

}  // namespace
}  // namespace tissuesim
