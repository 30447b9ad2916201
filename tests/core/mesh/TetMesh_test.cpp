// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetMesh.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "mesh/BlockMesher.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {
namespace {

TetMesh twoTets() {
  TetMesh mesh;
  mesh.nodes_m.resize(3, 5);
  mesh.nodes_m << 0, 1, 0, 0, 1,  //
      0, 0, 1, 0, 1,              //
      0, 0, 0, 1, 1;
  mesh.tets.resize(4, 2);
  mesh.tets << 0, 1, 1, 2, 2, 3, 3, 4;
  return mesh;
}

TEST(TetMesh, SignedVolume) {
  const TetMesh mesh = twoTets();
  EXPECT_NEAR(signedTetVolume(mesh.nodes_m, mesh.tets, 0), 1.0 / 6.0, 1e-15);
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_LT(signedTetVolume(a, c, b, d), 0.0);
}

TEST(TetMesh, InspectionFindsInvertedAndSliverTets) {
  TetMesh mesh = twoTets();
  EXPECT_TRUE(inspectTets(mesh).invertedTets.empty());
  std::swap(mesh.tets(0, 1), mesh.tets(1, 1));
  const TetQualityReport inverted = inspectTets(mesh);
  ASSERT_EQ(inverted.invertedTets.size(), 1u);
  EXPECT_EQ(inverted.invertedTets[0], 1);

  TetMesh sliver = twoTets();
  sliver.nodes_m.col(3) << 0.5, 0.5, 1e-9;  // tet 0 nearly flat
  const TetQualityReport flat = inspectTets(sliver);
  ASSERT_FALSE(flat.slivers.empty());
  EXPECT_EQ(flat.slivers[0], 0);
}

TEST(TetMesh, ValidationNamesTheProblem) {
  TetMesh mesh = twoTets();
  EXPECT_NO_THROW(validateTetMesh(mesh, "m"));
  mesh.tets(3, 1) = 9;
  try {
    validateTetMesh(mesh, "m");
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("tet 1 refers to node 9"), std::string::npos);
  }
  mesh = twoTets();
  mesh.nodes_m(1, 2) = std::nan("");
  EXPECT_THROW(validateTetMesh(mesh, "m"), std::invalid_argument);
  mesh = twoTets();
  mesh.tets(1, 0) = 0;
  EXPECT_THROW(validateTetMesh(mesh, "m"), std::invalid_argument);
  EXPECT_THROW(validateTetMesh(TetMesh{}, "m"), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim

namespace tissuesim {
namespace {

TEST(TetMesh, BoundaryFacesAreTheClosedOutwardSurface) {
  const TetMesh block = makeBlockMesh({0.02, 0.01, 0.03}, {2, 1, 3});
  const Eigen::Matrix3Xi faces = boundaryFaces(block);
  EXPECT_EQ(faces.cols(), 2 * 2 * (2 * 1 + 1 * 3 + 3 * 2));
  // Outward orientation: the divergence theorem gives the block's volume, positive.
  double volume = 0.0;
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    volume += block.nodes_m.col(faces(0, f))
                  .dot(block.nodes_m.col(faces(1, f)).cross(block.nodes_m.col(faces(2, f)))) /
              6.0;
  }
  EXPECT_NEAR(volume, 0.02 * 0.01 * 0.03, 1e-15);
}

TEST(TriangleSurface, ARayFindsTheFirstTriangleItCrosses) {
  const TetMesh block = makeBlockMesh({0.02, 0.02, 0.01}, {2, 2, 1});
  const Eigen::Matrix3Xi faces = boundaryFaces(block);
  Eigen::Vector3d crossing;
  // From above, down: the top face (not the bottom one behind it).
  ASSERT_TRUE(firstCrossing(block.nodes_m, faces, {0.007, 0.013, 0.05}, -Eigen::Vector3d::UnitZ(),
                            crossing));
  EXPECT_LT((crossing - Eigen::Vector3d(0.007, 0.013, 0.01)).norm(), 1e-15);
  // From inside, up: the top face again; beside the block or pointing away: nothing.
  ASSERT_TRUE(firstCrossing(block.nodes_m, faces, {0.003, 0.004, 0.002}, Eigen::Vector3d::UnitZ(),
                            crossing));
  EXPECT_NEAR(crossing.z(), 0.01, 1e-15);
  EXPECT_FALSE(
      firstCrossing(block.nodes_m, faces, {0.03, 0.01, 0.05}, -Eigen::Vector3d::UnitZ(), crossing));
  EXPECT_FALSE(
      firstCrossing(block.nodes_m, faces, {0.01, 0.01, 0.05}, Eigen::Vector3d::UnitZ(), crossing));
}

}  // namespace
}  // namespace tissuesim
