// SPDX-License-Identifier: Apache-2.0
#include "mesh/LatticeMesher.h"

#include <gtest/gtest.h>

#include "mesh/SurfaceReader.h"

namespace tissuesim {
namespace {

TriangleSurface liverSurface() {
  return readSurface(std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-smooth.obj", {0.03, ""});
}

TEST(LatticeMesher, FillsTheSurfaceWithGoodTets) {
  const TriangleSurface surface = liverSurface();
  const TetMesh mesh = meshInterior(surface, {0.012});
  const TetQualityReport quality = inspectTets(mesh);
  EXPECT_TRUE(quality.invertedTets.empty());
  EXPECT_TRUE(quality.slivers.empty());
  EXPECT_NEAR(quality.minDihedral_deg, 45.0, 1e-6);
  EXPECT_NEAR(quality.maxDihedral_deg, 90.0, 1e-6);
  EXPECT_GT(quality.minRadiusRatio, 0.7);
  // Volume within the staircase error of the surface's.
  EXPECT_NEAR(quality.totalVolume_m3 / enclosedVolume(surface), 1.0, 0.05);
  // Every kept cube's centre is inside: winding number 1 there. A Kuhn tet's longest edge is
  // its cube's diagonal, whose midpoint is the cube's centre.
  for (Eigen::Index t = 0; t < mesh.tetCount(); t += 97) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double longest = 0.0;
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const Eigen::Vector3d a = mesh.nodes_m.col(mesh.tets(i, t)),
                              b = mesh.nodes_m.col(mesh.tets(j, t));
        if ((b - a).norm() > longest) {
          longest = (b - a).norm();
          centre = (a + b) / 2.0;
        }
      }
    }
    EXPECT_NEAR(windingNumber(surface, centre), 1.0, 0.01);
  }
}

TEST(LatticeMesher, HitsASpringTarget) {
  const TriangleSurface surface = liverSurface();
  for (const int target : {1000, 5300}) {
    const TetMesh mesh = meshInterior(surface, {edgeLengthForSpringCount(surface, target)});
    EXPECT_NEAR(static_cast<double>(countUniqueEdges(mesh)), target, 0.1 * target);
  }
}

TEST(LatticeMesher, RefusesNonsense) {
  EXPECT_THROW(meshInterior(liverSurface(), {0.0}), std::invalid_argument);
  EXPECT_THROW(meshInterior(liverSurface(), {1e-5}), std::invalid_argument);  // 10^10 cells
  EXPECT_THROW(meshInterior(liverSurface(), {10.0}), std::invalid_argument);  // no centre inside
}

}  // namespace
}  // namespace tissuesim
