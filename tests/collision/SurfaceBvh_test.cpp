// SPDX-License-Identifier: Apache-2.0
#include "collision/SurfaceBvh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

// A 2 x 2 m square in the z = 0 plane, two triangles.
Eigen::MatrixX3d square(double z) {
  Eigen::MatrixX3d v(4, 3);
  v << -1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z;
  return v;
}
Eigen::MatrixX3i squareTriangles() {
  Eigen::MatrixX3i f(2, 3);
  f << 0, 1, 2, 0, 2, 3;
  return f;
}

Capsule verticalProbe(double tipHeight) {
  // Capsule along z: radius 0.05, cylinder 0.2; its lowest point is centre - 0.1 - 0.05.
  Capsule probe{0.05, 0.2, Eigen::Isometry3d::Identity()};
  probe.pose.translation() = Eigen::Vector3d(0.3, 0.2, tipHeight + 0.15);
  return probe;
}

TEST(SurfaceBvh, DistanceFromCapsuleToSurface) {
  const SurfaceBvh bvh(square(0.0), squareTriangles());
  const CapsuleSurfaceDistance d = bvh.distanceTo(verticalProbe(0.3));
  EXPECT_FALSE(d.isColliding);
  EXPECT_NEAR(d.distance_m, 0.3, 1e-6);
  EXPECT_NEAR(d.pointOnSurface_m.z(), 0.0, 1e-6);
  EXPECT_NEAR(d.pointOnSurface_m.x(), 0.3, 1e-6);
  EXPECT_NEAR(d.pointOnCapsule_m.z(), 0.3, 1e-6);
  EXPECT_GE(d.triangle, 0);
}

TEST(SurfaceBvh, ContactIsReported) {
  const SurfaceBvh bvh(square(0.0), squareTriangles());
  const CapsuleSurfaceDistance d = bvh.distanceTo(verticalProbe(-0.02));
  EXPECT_TRUE(d.isColliding);
  EXPECT_EQ(d.distance_m, 0.0);
}

TEST(SurfaceBvh, RefitFollowsTheMovedSurface) {
  SurfaceBvh bvh(square(0.0), squareTriangles());
  bvh.refit(square(0.1));
  EXPECT_NEAR(bvh.distanceTo(verticalProbe(0.3)).distance_m, 0.2, 1e-6);
  bvh.refit(square(0.35));
  EXPECT_TRUE(bvh.distanceTo(verticalProbe(0.3)).isColliding);
}

// A 20 x 20 grid over [-1, 1]^2 at height(x, y), 800 triangles: a tree of many levels.
Eigen::MatrixX3d grid(double amplitude, double phase) {
  Eigen::MatrixX3d v(21 * 21, 3);
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const double x = -1.0 + 0.1 * i, y = -1.0 + 0.1 * j;
      v.row(i + 21 * j) << x, y, amplitude * std::sin(3.0 * x + phase) * std::cos(2.0 * y - phase);
    }
  return v;
}
Eigen::MatrixX3i gridTriangles() {
  Eigen::MatrixX3i f(800, 3);
  int t = 0;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const int a = i + 21 * j;
      f.row(t++) << a, a + 1, a + 22;
      f.row(t++) << a, a + 22, a + 21;
    }
  return f;
}

// The refitted tree finds exactly the triangles a tree built afresh on the moved surface finds,
// for probes all over it (a stale box would hide a triangle that moved into the probe).
TEST(SurfaceBvh, RefittedTreeFindsWhatANewTreeFinds) {
  SurfaceBvh refitted(grid(0.0, 0.0), gridTriangles());
  for (const double phase : {0.4, 1.3}) {
    const Eigen::MatrixX3d moved = grid(0.3, phase);
    refitted.refit(moved);
    const SurfaceBvh fresh(moved, gridTriangles());
    int probesTouching = 0;
    for (double x = -0.9; x < 0.95; x += 0.15) {
      for (double y = -0.9; y < 0.95; y += 0.15) {
        Capsule probe{0.04, 0.3, Eigen::Isometry3d::Identity()};
        probe.pose.translation() = Eigen::Vector3d(x, y, 0.1 + 0.15 + 0.04);
        std::vector<int> found, expected;
        refitted.touchedTriangles(probe, found);
        fresh.touchedTriangles(probe, expected);
        std::sort(found.begin(), found.end());
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(found, expected) << "probe at " << x << ", " << y;
        probesTouching += expected.empty() ? 0 : 1;
      }
    }
    EXPECT_GT(probesTouching, 20);       // the surface's crests reach the probes
    EXPECT_LT(probesTouching, 13 * 13);  // and its troughs do not
  }
}

TEST(SurfaceBvh, RejectsBadInput) {
  Eigen::MatrixX3i bad = squareTriangles();
  bad(1, 2) = 4;
  EXPECT_THROW(SurfaceBvh(square(0.0), bad), std::invalid_argument);
  EXPECT_THROW(SurfaceBvh(Eigen::MatrixX3d(0, 3), Eigen::MatrixX3i(0, 3)), std::invalid_argument);
  SurfaceBvh bvh(square(0.0), squareTriangles());
  EXPECT_THROW(bvh.refit(Eigen::MatrixX3d::Zero(3, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
