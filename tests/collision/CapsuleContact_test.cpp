// SPDX-License-Identifier: Apache-2.0
#include "collision/CapsuleContact.h"

#include <gtest/gtest.h>

#include "mesh/BlockMesher.h"

namespace tissuesim {
namespace {

// A 4 x 4 x 2 cm block, top face at z = 0.02; the probe comes down on its middle.
class CapsuleContactTest : public ::testing::Test {
 protected:
  TetMesh m_block = makeBlockMesh({0.04, 0.04, 0.02}, {8, 8, 4});
  CapsuleContact m_contact{m_block, {0.0025, 0.1, 300.0}};

  /// The contacts found with the probe's tip at `tip`, evaluated on `x` (the block at rest by
  /// default): the reaction on the tool, and the forces on the nodes into `forces`.
  ContactResult press(const Eigen::Vector3d& tip, Eigen::Matrix3Xd* forces = nullptr,
                      const Eigen::Matrix3Xd* x = nullptr) {
    const Eigen::Matrix3Xd& at = x != nullptr ? *x : m_block.nodes_m;
    PenaltyContactSet contacts;
    m_contact.findContacts(at, {tip, {0, 0, -1}}, contacts);
    if (forces != nullptr) contacts.addForces(at, *forces);
    m_found = static_cast<int>(contacts.contacts().size());
    return contacts.reaction(at, tip);
  }
  ContactResult pressTo(double tipHeight, Eigen::Matrix3Xd* forces = nullptr) {
    return press({0.02, 0.02, tipHeight}, forces);
  }
  int m_found = 0;  ///< contacts found by the last press, active or not
};

TEST_F(CapsuleContactTest, NoForceBeforeContact) {
  EXPECT_EQ(m_contact.boundaryTriangleCount(), 2 * 2 * (8 * 8 + 8 * 4 + 4 * 8));
  const ContactResult above = pressTo(0.021);
  EXPECT_EQ(above.contactNodes, 0);
  EXPECT_EQ(above.toolForce_N.norm(), 0.0);
  EXPECT_GT(m_found, 0);  // 1 mm above: found, to activate if the tissue comes up in the step
  pressTo(0.0215);
  EXPECT_EQ(m_found, 0);  // past the half-radius margin: nothing
}

TEST_F(CapsuleContactTest, ForceRisesMonotonicallyWithDepthAndPushesTheToolBack) {
  double previous = 0.0;
  for (double depth = 0.0005; depth <= 0.0025; depth += 0.0005) {
    Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, m_block.nodeCount());
    const ContactResult result = pressTo(0.02 - depth, &forces);
    ASSERT_GT(result.contactNodes, 0) << depth;
    EXPECT_GT(result.toolForce_N.z(), previous) << depth;  // pushes the tool up, more and more
    EXPECT_NEAR(result.toolForce_N.x(), 0.0, 1e-9);
    previous = result.toolForce_N.z();
    // Action and reaction.
    EXPECT_LT((forces.rowwise().sum() + result.toolForce_N).norm(), 1e-12);
    EXPECT_LE(result.maxPenetration_m, 0.0025);
  }
}

TEST_F(CapsuleContactTest, AProbeBetweenNodesIsCaughtByTheFace) {
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, m_block.nodeCount());
  // Nodes every 5 mm; a 2.5 mm probe centred between four of them.
  const ContactResult result = press({0.0225, 0.0225, 0.019}, &forces);
  EXPECT_GT(result.contactNodes, 0);
  EXPECT_GT(result.toolForce_N.z(), 0.0);
  EXPECT_NEAR(result.maxPenetration_m, 0.001, 1e-9);
}

TEST_F(CapsuleContactTest, RefitFollowsTheDeformedSurface) {
  Eigen::Matrix3Xd lowered = m_block.nodes_m;
  lowered.row(2).array() -= 0.005;  // the whole block 5 mm lower
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, m_block.nodeCount());
  EXPECT_EQ(press({0.02, 0.02, 0.018}, &forces, &lowered).contactNodes, 0);
  EXPECT_GT(press({0.02, 0.02, 0.014}, &forces, &lowered).contactNodes, 0);
}

TEST_F(CapsuleContactTest, APointOfTheSurfaceIsPushedOnceWhateverTheFacesThatShareIt) {
  // The tip 0.01 mm into the top face over a node (shared by several faces), over the middle of
  // an edge (two faces) and over a face's inside: the same point contact each time, k delta,
  // one pushing contact. Counted once per face that shares the point, a node pushed back with
  // its valence times k; at a deep hold, which faces shared it changed from step to step and
  // the contact never settled.
  constexpr double kDepth = 1e-5;
  const double stiffness = 300.0;                                             // m_contact's
  for (const Eigen::Vector3d& at : {Eigen::Vector3d(0.02, 0.02, 0.0),         // a node
                                    Eigen::Vector3d(0.0225, 0.02, 0.0),       // an edge's middle
                                    Eigen::Vector3d(0.0212, 0.0228, 0.0)}) {  // inside a face
    const ContactResult result = press({at.x(), at.y(), 0.02 - kDepth});
    EXPECT_EQ(result.contactNodes, 1) << at.transpose();
    EXPECT_NEAR(result.toolForce_N.z(), stiffness * kDepth, 1e-9 * stiffness * kDepth)
        << at.transpose();
  }
}

}  // namespace
}  // namespace tissuesim
