// SPDX-License-Identifier: Apache-2.0
#include "sim/ToolClearance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "mesh/BlockMesher.h"
#include "mesh/SegmentTriangleDistance.h"

namespace tissuesim {
namespace {

/// The capsule's distance to every boundary triangle, less its radius: the clearance by brute
/// force.
double everyFace(const TetMesh& mesh, const Eigen::Matrix3Xd& x, const Eigen::Vector3d& a,
                 const Eigen::Vector3d& b, double radius_m) {
  const Eigen::Matrix3Xi faces = boundaryFaces(mesh);
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    nearest = std::min(nearest, closestSegmentTriangle(a, b, x.col(faces(0, f)), x.col(faces(1, f)),
                                                       x.col(faces(2, f)))
                                    .distance);
  }
  return nearest - radius_m;
}

TEST(ToolClearance, ExactWithinItsReachAndNeverMoreThanTheClearanceBeyond) {
  // A block of 2 cm cells, moved a little off its rest shape, and capsules thrown at random
  // around it: within 5 mm the clearance is the brute force's, beyond it never more (the cheap
  // bound of the faces further off), and inside the block it is at most -R.
  const TetMesh mesh = makeBlockMesh({0.04, 0.04, 0.02}, {2, 2, 1});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> wobble(-0.001, 0.001), around(-0.03, 0.07),
      unit(-1.0, 1.0);
  Eigen::Matrix3Xd x = mesh.nodes_m;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += wobble(random);
  const ToolClearance clearance(mesh);
  ASSERT_EQ(clearance.faceCount(), boundaryFaces(mesh).cols());
  const double radius_m = 0.0025, within_m = 0.005;
  int exact = 0, bounded = 0, inside = 0;
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Vector3d a(around(random), around(random), 0.5 * around(random));
    Eigen::Vector3d direction(unit(random), unit(random), unit(random));
    if (direction.norm() < 0.1) continue;
    const Eigen::Vector3d b = a + 0.05 * direction.normalized();
    const double expected = everyFace(mesh, x, a, b, radius_m);
    const double found = clearance(x, a, b, radius_m, within_m);
    EXPECT_LE(found, expected + 1e-12) << n;
    if (expected < within_m) {
      EXPECT_NEAR(found, expected, 1e-12) << n;
      ++exact;
      if (expected <= -radius_m + 1e-12) ++inside;
    } else if (found < expected - 1e-6) {
      ++bounded;
    }
  }
  EXPECT_GT(exact, 100);
  EXPECT_GT(inside, 10);
  EXPECT_GT(bounded, 100) << "the far faces are bounded, not measured";
}

TEST(ToolClearance, AMeshWithNoBoundaryIsInfinitelyFar) {
  const ToolClearance clearance(TetMesh{});
  EXPECT_EQ(clearance.faceCount(), 0);
  EXPECT_EQ(clearance(Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                      0.001, 0.005),
            std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace tissuesim
