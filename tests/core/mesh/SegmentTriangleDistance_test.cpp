// SPDX-License-Identifier: Apache-2.0
#include "mesh/SegmentTriangleDistance.h"

#include <random>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

/// Brute force: the least distance over a fine sampling of the segment and the triangle.
double sampledDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                       const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c) {
  constexpr int kSteps = 60;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSteps; ++i) {
    const Eigen::Vector3d onSegment = p0 + (static_cast<double>(i) / kSteps) * (p1 - p0);
    for (int u = 0; u <= kSteps; ++u) {
      for (int v = 0; u + v <= kSteps; ++v) {
        const double wu = static_cast<double>(u) / kSteps, wv = static_cast<double>(v) / kSteps;
        best = std::min(best, (a + wu * (b - a) + wv * (c - a) - onSegment).norm());
      }
    }
  }
  return best;
}

TEST(SegmentTriangleDistance, MatchesBruteForceOnRandomCases) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto point = [&] {
    return Eigen::Vector3d(uniform(random), uniform(random), uniform(random));
  };
  for (int trial = 0; trial < 60; ++trial) {
    const Eigen::Vector3d p0 = point(), p1 = point(), a = point(), b = point(), c = point();
    const SegmentTriangleClosest closest = closestSegmentTriangle(p0, p1, a, b, c);
    const double sampled = sampledDistance(p0, p1, a, b, c);
    // Exact is never above the sampling, and the sampling (step ~ 0.05) is close above it.
    EXPECT_LE(closest.distance, sampled + 1e-12) << trial;
    EXPECT_GT(closest.distance, sampled - 0.08) << trial;
    // The points are what they claim to be.
    EXPECT_NEAR((closest.onTriangle - closest.onSegment).norm(), closest.distance, 1e-12);
    const Eigen::Vector3d fromWeights =
        closest.weights[0] * a + closest.weights[1] * b + closest.weights[2] * c;
    EXPECT_LT((fromWeights - closest.onTriangle).norm(), 1e-12) << trial;
    EXPECT_NEAR(closest.weights.sum(), 1.0, 1e-12);
    EXPECT_GE(closest.weights.minCoeff(), -1e-12);
  }
}

TEST(SegmentTriangleDistance, KnownCases) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // A tip above the face: straight down onto it.
  const SegmentTriangleClosest above =
      closestSegmentTriangle({0.2, 0.2, 2}, {0.2, 0.2, 0.5}, a, b, c);
  EXPECT_NEAR(above.distance, 0.5, 1e-15);
  EXPECT_LT((above.onTriangle - Eigen::Vector3d(0.2, 0.2, 0)).norm(), 1e-15);
  EXPECT_LT((above.weights - Eigen::Vector3d(0.6, 0.2, 0.2)).norm(), 1e-15);
  // Through the face: distance 0 at the crossing.
  const SegmentTriangleClosest through =
      closestSegmentTriangle({0.2, 0.2, 1}, {0.2, 0.2, -1}, a, b, c);
  EXPECT_LT(through.distance, 1e-15);
  EXPECT_LT((through.onSegment - Eigen::Vector3d(0.2, 0.2, 0)).norm(), 1e-15);
  // Beside an edge, parallel to it: the edge's nearest point.
  const SegmentTriangleClosest beside =
      closestSegmentTriangle({0.5, -0.3, 0}, {0.5, -0.3, 1}, a, b, c);
  EXPECT_NEAR(beside.distance, 0.3, 1e-15);
  EXPECT_NEAR(beside.weights[2], 0.0, 1e-12);
}

}  // namespace
}  // namespace tissuesim
