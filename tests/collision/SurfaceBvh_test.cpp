#include "SurfaceBvh.h"

#include <stdexcept>

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
