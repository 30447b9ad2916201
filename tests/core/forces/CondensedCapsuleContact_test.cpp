// SPDX-License-Identifier: Apache-2.0
// The capsule's contact against a condensed compliance: a single node on a spring meets the
// closed form; on a coupled compliance with points between nodes, the forces it settles to are
// CapsulePenalty's (an independent evaluation of the same penalty) at the positions it settles
// to; a warm start settles at once; the normals' turning in the Hessian settles a hard press in
// fewer iterations than Gauss-Newton's; held points (the grasp) meet the closed form on a spring
// and balance the body on the coupled patch; and bad points are refused.

#include "forces/CondensedCapsuleContact.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>

#include "forces/CapsuleGap.h"
#include "forces/CapsulePenalty.h"
#include "forces/SmoothedPenalty.h"

namespace tissuesim {
namespace {

constexpr double kRadius_m = 0.0025;

/// A vertical capsule whose lowest point is `depth_m` below z = 0.
struct Probe {
  Eigen::Vector3d tip, top;
  explicit Probe(double depth_m, double x_m = 0.0)
      : tip(x_m, 0.0, kRadius_m - depth_m), top(x_m, 0.0, kRadius_m - depth_m + 0.1) {}
};

TEST(CondensedCapsuleContact, ANodeOnASpringMeetsTheClosedForm) {
  // One node at the origin on an isotropic spring k_b, one point on it with penalty k_p:
  // k_b u = k_p (d - u - d_s / 2), d_s the penalty's smoothing (its slope past d_s is g + d_s/2).
  constexpr double kBody_N_m = 200.0, kPenalty_N_m = 5e4, depth_m = 0.002;
  CondensedCapsuleContact contact;
  contact.setCandidates({7});
  contact.compliance() = Eigen::Matrix3d::Identity() / kBody_N_m;
  contact.freePositions().setZero();
  contact.setPoints(Eigen::Matrix3Xi::Zero(3, 1), Eigen::Vector3d(1.0, 0.0, 0.0),
                    Eigen::VectorXd::Constant(1, kPenalty_N_m));
  const Probe probe(depth_m);
  const Eigen::Vector3d reaction = contact.solve(probe.tip, probe.top, kRadius_m);
  EXPECT_TRUE(contact.converged());
  const double u =
      kPenalty_N_m * (depth_m - 0.5 * kPenaltySmoothing_m) / (kBody_N_m + kPenalty_N_m);
  EXPECT_NEAR(reaction.z(), kBody_N_m * u, 1e-6);
  EXPECT_NEAR(reaction.head<2>().norm(), 0.0, 1e-9);
  EXPECT_NEAR(contact.positions()(2, 0), -u, 1e-9);
  EXPECT_NEAR(contact.nodeForces()(2, 0), -kBody_N_m * u, 1e-6);
}

TEST(CondensedCapsuleContact, TheSecantScaleIsTheStiffeningLawsOwn) {
  // S(F) = (displacement from F_lin to F under k = k_lin (1 + b (F - F_lin))) / ((F - F_lin) /
  // k_lin), the displacement by the trapezoidal rule here; past the range z = b (F - F_lin) is
  // held to, the law is not extrapolated.
  constexpr double kRate_per_N = 4.0, kLinearised_N = 0.2;
  for (const double load_N : {0.0, 0.05, 0.19, 0.2, 0.21, 0.5, 0.8}) {
    double compliance_integral = 0.0;  // integral of k_lin / k(F) dF from F_lin to F
    constexpr int kPieces = 20000;
    for (int i = 0; i < kPieces; ++i) {
      const double a = kLinearised_N + (load_N - kLinearised_N) * i / kPieces;
      const double b = kLinearised_N + (load_N - kLinearised_N) * (i + 1) / kPieces;
      compliance_integral += 0.5 * (b - a) *
                             (1.0 / (1.0 + kRate_per_N * (a - kLinearised_N)) +
                              1.0 / (1.0 + kRate_per_N * (b - kLinearised_N)));
    }
    const double expected =
        load_N == kLinearised_N ? 1.0 : compliance_integral / (load_N - kLinearised_N);
    EXPECT_NEAR(CondensedCapsuleContact::secantScale(load_N, kLinearised_N, kRate_per_N), expected,
                1e-8)
        << load_N;
  }
  EXPECT_EQ(CondensedCapsuleContact::secantScale(0.7, kLinearised_N, 0.0), 1.0) << "no rate";
  EXPECT_DOUBLE_EQ(CondensedCapsuleContact::secantScale(5.0, kLinearised_N, kRate_per_N),
                   std::log1p(2.51) / 2.51)
      << "at most twice the tangent's stiffness";
  EXPECT_DOUBLE_EQ(CondensedCapsuleContact::secantScale(0.0, kLinearised_N, 10.0),
                   std::log1p(-0.9) / -0.9);
  EXPECT_GT(CondensedCapsuleContact::secantScale(0.0, kLinearised_N, kRate_per_N), 1.0)
      << "unloaded, softer than the tangent";
  EXPECT_LT(CondensedCapsuleContact::secantScale(0.5, kLinearised_N, kRate_per_N), 1.0)
      << "loaded further, stiffer";
}

TEST(CondensedCapsuleContact, AStiffeningNodePressedFurtherMeetsItsLaw) {
  // One node, linearised pressed down by F_lin (tangent k_lin there, B = C = 1 / k_lin), whose
  // stiffness grows as k_lin (1 + b (F - F_lin)): held at a fixed pose, repeated solves (each
  // taking the scale from the last one's force) settle where the node's displacement from its
  // linearised place is the law's integral of dF / k(F), the probe's penalty balancing F. Drawn
  // back, the node comes to the law's unloaded place, above where the tangent alone would have
  // put it.
  constexpr double kTangent_N_m = 200.0, kPenalty_N_m = 5e4, kLinearised_N = 0.1;
  constexpr double kRate_per_N = 3.0;
  const double linearised_m = -kLinearised_N / kTangent_N_m;  // the node pressed down there
  CondensedCapsuleContact contact;
  contact.setCandidates({0});
  contact.compliance() = Eigen::Matrix3d::Identity() / kTangent_N_m;
  contact.freePositions().setZero();  // where the tangent puts it with no load
  contact.setPoints(Eigen::Matrix3Xi::Zero(3, 1), Eigen::Vector3d(1.0, 0.0, 0.0),
                    Eigen::VectorXd::Constant(1, kPenalty_N_m));
  contact.bodyAtRest() = Eigen::Matrix3Xd::Zero(3, 1);
  contact.bodyResponse() = Eigen::MatrixXd::Identity(3, 3) / kTangent_N_m;
  const Eigen::Matrix3Xd loadResponse = Eigen::Vector3d(0.0, 0.0, linearised_m);
  contact.setStiffening(loadResponse, kLinearised_N, kRate_per_N);
  // The law: the node at z(F) = linearised - ln(1 + b (F - F_lin)) / (b k_lin).
  const auto nodeAt = [&](double load_N) {
    return linearised_m -
           std::log1p(kRate_per_N * (load_N - kLinearised_N)) / (kRate_per_N * kTangent_N_m);
  };
  const double depth_m = 0.002;  // the node below the hemisphere's centre
  const Probe probe(depth_m);
  for (int solve = 0; solve < 40; ++solve) contact.solve(probe.tip, probe.top, kRadius_m);
  EXPECT_TRUE(contact.converged());
  const double force_N = -contact.nodeForces()(2, 0);
  const double node_m = contact.positions()(2, 0);
  // The penalty balances F at the node's depth inside the probe (its slope past the smoothing
  // is g + d_s / 2), to the solve's tolerance (1e-5 N a node), and the node is where the law
  // puts it under F.
  EXPECT_NEAR(force_N, kPenalty_N_m * (depth_m + node_m - 0.5 * kPenaltySmoothing_m), 1e-5);
  EXPECT_NEAR(node_m, nodeAt(force_N), 1e-9);
  EXPECT_GT(force_N, 1.4 * (kLinearised_N + kTangent_N_m * (depth_m + linearised_m)))
      << "stiffer than the tangent";
  Eigen::Matrix3Xd body(3, 1);
  contact.bodyPositions(body);
  EXPECT_NEAR(body(2, 0), node_m, 1e-12) << "the body follows the scaled response";
  // Drawn back clear: the scale of no load, the node at the law's unloaded place.
  const Probe clear(-0.01);
  for (int solve = 0; solve < 3; ++solve) contact.solve(clear.tip, clear.top, kRadius_m);
  EXPECT_NEAR(contact.positions()(2, 0), nodeAt(0.0), 1e-12);
  EXPECT_GT(contact.positions()(2, 0), 0.0) << "past where the tangent alone settles";
  EXPECT_THROW(contact.setStiffening(loadResponse, kLinearised_N, -1.0), std::invalid_argument);
  EXPECT_THROW(contact.setStiffening(Eigen::Matrix3Xd::Zero(3, 2), kLinearised_N, kRate_per_N),
               std::invalid_argument);
}

/// Nine nodes of a 3 x 3 grid 2 mm apart at z = 0, a random symmetric positive definite
/// compliance coupling them, and points between them (the grid's eight triangles, four points
/// each), their penalty 1e4 N/m.
struct CoupledPatch {
  CondensedCapsuleContact contact;
  std::vector<CapsulePenalty::Point> points;
  Eigen::Matrix3Xi localNodes;
  Eigen::Matrix3Xd weights;
  Eigen::VectorXd stiffness;

  CoupledPatch() {
    std::vector<int> nodes;
    for (int j = 0; j < 9; ++j) nodes.push_back(100 + j);  // ids of a larger body
    contact.setCandidates(nodes);
    for (int j = 0; j < 9; ++j)
      contact.freePositions().col(j) = Eigen::Vector3d(0.002 * (j % 3 - 1), 0.002 * (j / 3 - 1), 0);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::MatrixXd a(27, 27);
    for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = uniform(random);
    contact.compliance() =
        (a * a.transpose() / 27.0 + Eigen::MatrixXd::Identity(27, 27)) * 2e-3;  // m/N
    const Eigen::Vector3d corners[4] = {{1.0 / 6, 1.0 / 6, 2.0 / 3},
                                        {2.0 / 3, 1.0 / 6, 1.0 / 6},
                                        {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                        {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    std::vector<Eigen::Vector3i> triangles;
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) {
        const int n = 3 * r + c;
        triangles.push_back({n, n + 1, n + 4});
        triangles.push_back({n, n + 4, n + 3});
      }
    }
    const auto count = static_cast<Eigen::Index>(4 * triangles.size());
    localNodes.resize(3, count);
    weights.resize(3, count);
    stiffness.setConstant(count, 1e4);
    Eigen::Index p = 0;
    for (const Eigen::Vector3i& triangle : triangles) {
      for (const Eigen::Vector3d& w : corners) {
        localNodes.col(p) = triangle;
        weights.col(p) = w;
        points.push_back({{nodes[static_cast<std::size_t>(triangle[0])],
                           nodes[static_cast<std::size_t>(triangle[1])],
                           nodes[static_cast<std::size_t>(triangle[2])]},
                          w,
                          1e4});
        ++p;
      }
    }
    contact.setPoints(localNodes, weights, stiffness);
  }
};

/// CapsulePenalty (an independent evaluation of the same penalty) on the patch where its last
/// solve settled, in the larger body's numbering: the largest imbalance between its forces and
/// the body's on a candidate (N), and its reaction on the probe.
struct PenaltyAtTheSettledPatch {
  double largestImbalance_N;
  Eigen::Vector3d reaction_N;
  Eigen::Matrix3Xd gradient_N;  ///< the penalty's dE/dx on the candidates (3 by 9)

  PenaltyAtTheSettledPatch(const CoupledPatch& patch, const Probe& probe) {
    Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 109);
    for (int j = 0; j < 9; ++j) x.col(100 + j) = patch.contact.positions().col(j);
    CapsulePenalty penalty(patch.points);
    penalty.tip_m = probe.tip;
    penalty.top_m = probe.top;
    penalty.radius_m = kRadius_m;
    Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, 109);
    penalty.add(x, &gradient, nullptr);
    gradient_N = gradient.rightCols(9);
    largestImbalance_N = (patch.contact.nodeForces() + gradient_N).cwiseAbs().maxCoeff();
    reaction_N = penalty.reaction(x);
  }
};

TEST(CondensedCapsuleContact, ItSettlesWhereThePenaltysForcesBalanceTheBody) {
  CoupledPatch patch;
  const Probe probe(0.0015, 0.0007);
  const Eigen::Vector3d reaction = patch.contact.solve(probe.tip, probe.top, kRadius_m);
  ASSERT_TRUE(patch.contact.converged());
  EXPECT_GT(reaction.z(), 0.1);  // pressed down, the nodes push up
  // Within the solve's tolerance, 1e-5 N on each candidate's force component (nine of them).
  const PenaltyAtTheSettledPatch settled(patch, probe);
  EXPECT_LT(settled.largestImbalance_N, 1e-5);
  EXPECT_NEAR(patch.contact.residual_N(), settled.largestImbalance_N, 1e-9) << "what it reports";
  EXPECT_LT((reaction - settled.reaction_N).cwiseAbs().maxCoeff(), 9e-5);
  // The body's side: the forces are C^-1 (x - xFree).
  const Eigen::Matrix3Xd u = patch.contact.positions() - patch.contact.freePositions();
  const Eigen::VectorXd f =
      patch.contact.compliance().llt().solve(Eigen::Map<const Eigen::VectorXd>(u.data(), u.size()));
  EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(patch.contact.nodeForces().data(), 27) - f)
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
}

TEST(CondensedCapsuleContact, AWarmStartSettlesAtOnceAndTheBodyFollowsTheForces) {
  CoupledPatch patch;
  const Probe probe(0.001);
  const Eigen::Vector3d first = patch.contact.solve(probe.tip, probe.top, kRadius_m);
  EXPECT_GT(patch.contact.iterations(), 1);
  CoupledPatch again;
  again.contact.startFrom(patch.contact);
  const Eigen::Vector3d second = again.contact.solve(probe.tip, probe.top, kRadius_m);
  EXPECT_TRUE(again.contact.converged());
  EXPECT_LE(again.contact.iterations(), 1);
  EXPECT_LT((second - first).norm(), 1e-6);
  // The whole body: x = xRest + B f.
  again.contact.bodyAtRest() = Eigen::Matrix3Xd::Constant(3, 4, 0.5);
  again.contact.bodyResponse() = Eigen::MatrixXd::Identity(12, 27);
  Eigen::Matrix3Xd body;
  again.contact.bodyPositions(body);
  EXPECT_NEAR(body(2, 3), 0.5 + again.contact.nodeForces()(2, 3), 1e-15);
  EXPECT_NEAR(body(0, 0), 0.5 + again.contact.nodeForces()(0, 0), 1e-15);
}

TEST(CondensedCapsuleContact, AHeldNodeOnASpringMeetsTheClosedForm) {
  // One node on an isotropic spring k_b held by the grasp's spring k_h to a target d away, the
  // probe clear: k_b u = k_h (d - u), and the probe feels the node's pull, minus k_b u.
  constexpr double kBody_N_m = 200.0;
  CondensedCapsuleContact contact;
  contact.setCandidates({7});
  contact.compliance() = Eigen::Matrix3d::Identity() / kBody_N_m;
  contact.freePositions().setZero();
  contact.setPoints(Eigen::Matrix3Xi::Zero(3, 1), Eigen::Vector3d(1.0, 0.0, 0.0),
                    Eigen::VectorXd::Constant(1, 5e4));
  contact.setHeldPoints(Eigen::Matrix3Xi::Zero(3, 1), Eigen::Vector3d(1.0, 0.0, 0.0));
  contact.heldStiffness_N_m = 2000.0;
  ASSERT_EQ(contact.heldCount(), 1);
  EXPECT_EQ(contact.heldTargets().col(0), Eigen::Vector3d::Zero()) << "held where it is";
  const Eigen::Vector3d pull_m(0.001, -0.0005, 0.003);
  contact.heldTargets().col(0) = pull_m;
  const Probe clear(-0.01);
  const Eigen::Vector3d reaction = contact.solve(clear.tip, clear.top, kRadius_m);
  EXPECT_TRUE(contact.converged());
  const double k_h = contact.heldStiffness_N_m;
  const Eigen::Vector3d u = k_h / (kBody_N_m + k_h) * pull_m;
  EXPECT_LT((contact.positions().col(0) - u).norm(), 1e-9);
  EXPECT_LT((contact.heldPosition(0) - u).norm(), 1e-9);
  EXPECT_LT((reaction + kBody_N_m * u).norm(), 1e-6);
  EXPECT_EQ(contact.heldFreePosition(0), Eigen::Vector3d::Zero());
  // Released, it settles back where it was free, exactly.
  contact.setHeldPoints(Eigen::Matrix3Xi(3, 0), Eigen::Matrix3Xd(3, 0));
  EXPECT_EQ(contact.solve(clear.tip, clear.top, kRadius_m).norm(), 0.0);
  EXPECT_EQ(contact.positions(), contact.freePositions());
}

TEST(CondensedCapsuleContact, HeldPointsPressedByTheProbeBalanceTheBody) {
  // The coupled patch pressed by the probe, two of its points held to targets lifted 1 mm: the
  // candidates' forces are the penalty's (CapsulePenalty) plus the held springs' k_h (t - s),
  // spread by the points' weights, to the solve's tolerance.
  CoupledPatch patch;
  const Eigen::Matrix3Xi held = patch.localNodes.leftCols(2);
  const Eigen::Matrix3Xd heldWeights = patch.weights.leftCols(2);
  patch.contact.setHeldPoints(held, heldWeights);
  patch.contact.heldStiffness_N_m = 2000.0;
  const Eigen::Vector3d lift_m(0.0, 0.0, 0.001);
  for (Eigen::Index h = 0; h < 2; ++h) patch.contact.heldTargets().col(h) += lift_m;
  const Probe probe(0.001, 0.0007);
  const Eigen::Vector3d reaction = patch.contact.solve(probe.tip, probe.top, kRadius_m);
  ASSERT_TRUE(patch.contact.converged());
  const PenaltyAtTheSettledPatch penalty(patch, probe);
  Eigen::Matrix3Xd springs = Eigen::Matrix3Xd::Zero(3, 9);
  Eigen::Vector3d pull_N = Eigen::Vector3d::Zero();
  for (Eigen::Index h = 0; h < 2; ++h) {
    const Eigen::Vector3d f = patch.contact.heldStiffness_N_m *
                              (patch.contact.heldTargets().col(h) - patch.contact.heldPosition(h));
    pull_N += f;
    for (int a = 0; a < 3; ++a) springs.col(held(a, h)) += heldWeights(a, h) * f;
  }
  EXPECT_GT(pull_N.z(), 0.1) << "the held points are pulled up";
  // The candidates' forces from the body (C^-1 u) against the penalty's and the springs'.
  EXPECT_LT((patch.contact.nodeForces() + penalty.gradient_N - springs).cwiseAbs().maxCoeff(),
            1e-5);
  EXPECT_LT((reaction - (penalty.reaction_N - pull_N)).cwiseAbs().maxCoeff(), 9e-5);
}

TEST(CondensedCapsuleContact, NoContactNoForce) {
  CoupledPatch patch;
  const Probe above(-0.001);
  EXPECT_EQ(patch.contact.solve(above.tip, above.top, kRadius_m).norm(), 0.0);
  EXPECT_TRUE(patch.contact.converged());
  EXPECT_EQ(patch.contact.positions(), patch.contact.freePositions());
}

TEST(CondensedCapsuleContact, AWarmStartTheProbeHasLeftLetsGoExactly) {
  // A light press leaves forces on the nodes below the solve's tolerance; the next contact
  // starts from them with the probe gone. Touching nothing, settled is unloaded, exactly: a
  // force kept within the tolerance would stay on for good where each solve starts from the last.
  CoupledPatch pressed;
  // Pressed a tenth of a micrometre past the point nearest the round tip.
  const auto nearestGap_m = [&](double depth_m) {
    const Probe probe(depth_m);
    double nearest_m = 1.0;
    for (Eigen::Index p = 0; p < pressed.localNodes.cols(); ++p) {
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      for (int a = 0; a < 3; ++a)
        s += pressed.weights(a, p) * pressed.contact.freePositions().col(pressed.localNodes(a, p));
      nearest_m = std::min(nearest_m, capsuleGap(s, probe.tip, probe.top, kRadius_m).gap_m);
    }
    return nearest_m;
  };
  double depth_m = 0.0;
  for (int n = 0; n < 20; ++n) depth_m += nearestGap_m(depth_m) + 6e-8;
  ASSERT_NEAR(nearestGap_m(depth_m), -6e-8, 1e-9);
  const Probe light(depth_m);
  pressed.contact.solve(light.tip, light.top, kRadius_m);
  ASSERT_TRUE(pressed.contact.converged());
  const double largest_N = pressed.contact.nodeForces().cwiseAbs().maxCoeff();
  ASSERT_GT(largest_N, 0.0) << "it touched";
  ASSERT_LT(largest_N, 1e-5) << "below the tolerance";
  CoupledPatch left;
  left.contact.startFrom(pressed.contact);
  const Probe above(-0.001);
  EXPECT_EQ(left.contact.solve(above.tip, above.top, kRadius_m).norm(), 0.0);
  EXPECT_TRUE(left.contact.converged());
  EXPECT_EQ(left.contact.positions(), left.contact.freePositions());
  EXPECT_EQ(left.contact.nodeForces().cwiseAbs().maxCoeff(), 0.0);
}

TEST(CondensedCapsuleContact, BadHeldPointsAreRefused) {
  CoupledPatch patch;
  EXPECT_THROW(patch.contact.setHeldPoints(Eigen::Matrix3Xi::Constant(3, 1, 9),
                                           Eigen::Matrix3Xd::Constant(3, 1, 1.0 / 3)),
               std::invalid_argument);
  EXPECT_THROW(patch.contact.setHeldPoints(Eigen::Matrix3Xi::Zero(3, 2), Eigen::Matrix3Xd(3, 1)),
               std::invalid_argument);
}

TEST(CondensedCapsuleContact, BadPointsAreRefused) {
  CoupledPatch patch;
  Eigen::Matrix3Xi outside = patch.localNodes;
  outside(1, 3) = 9;
  EXPECT_THROW(patch.contact.setPoints(outside, patch.weights, patch.stiffness),
               std::invalid_argument);
  Eigen::VectorXd negative = patch.stiffness;
  negative[2] = -1.0;
  EXPECT_THROW(patch.contact.setPoints(patch.localNodes, patch.weights, negative),
               std::invalid_argument);
  EXPECT_THROW(patch.contact.setPoints(patch.localNodes, patch.weights, patch.stiffness.head(3)),
               std::invalid_argument);
  patch.contact.compliance()(0, 0) = -1.0;
  EXPECT_THROW(patch.contact.setPoints(patch.localNodes, patch.weights, patch.stiffness),
               std::invalid_argument);
}

TEST(CondensedCapsuleContact, TheNormalsTurningSettlesAHardPressInFewerIterations) {
  // The patch pressed 1.5 mm by the round tip, on and beside its middle, from rest: Gauss-Newton
  // alone (the normals' turning left out of the Hessian) takes 11 or 12 iterations to settle
  // here, converging only linearly as the pressed points slide round the tip; with the turning
  // added after its first three, 5 or 6. Settled where CapsulePenalty's forces balance the body.
  for (const double offset_m : {0.0, 0.0007, 0.0015}) {
    CoupledPatch patch;
    const Probe probe(0.0015, offset_m);
    const Eigen::Vector3d reaction = patch.contact.solve(probe.tip, probe.top, kRadius_m);
    ASSERT_TRUE(patch.contact.converged()) << offset_m;
    EXPECT_GT(reaction.z(), 1.0) << offset_m;
    EXPECT_LE(patch.contact.iterations(), 8) << offset_m;
    EXPECT_LT(PenaltyAtTheSettledPatch(patch, probe).largestImbalance_N, 1e-5) << offset_m;
  }
}

}  // namespace
}  // namespace tissuesim
