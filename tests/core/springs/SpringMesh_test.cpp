// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringMesh.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "mesh/BlockMesher.h"

namespace tissuesim {
namespace {

TEST(SpringMesh, OneTetHasSixSprings) {
  TetMesh tet;
  tet.nodes_m = Eigen::Matrix3d::Identity().replicate(1, 1);
  tet.nodes_m.conservativeResize(3, 4);
  tet.nodes_m.col(3).setZero();
  tet.tets.resize(4, 1);
  tet.tets << 3, 0, 1, 2;
  const SpringMesh mesh = buildSpringMesh(tet, 1000.0);
  EXPECT_EQ(mesh.springCount(), 6);
  const double volume = 1.0 / 6.0;
  EXPECT_NEAR(mesh.volume_m3.sum(), volume, 1e-15);
  EXPECT_NEAR(mesh.nodeMass_kg.sum(), 1000.0 * volume, 1e-12);
  for (Eigen::Index s = 0; s < 6; ++s) {
    EXPECT_LT(mesh.springs(0, s), mesh.springs(1, s));
    EXPECT_NEAR(mesh.volume_m3[s], volume / 6.0, 1e-15);
    const double expected =
        (mesh.springs(0, s) == 3 || mesh.springs(1, s) == 3) ? 1.0 : std::sqrt(2.0);
    EXPECT_NEAR(mesh.restLength_m[s], expected, 1e-15);
  }
}

TEST(SpringMesh, SharedEdgesAreMergedAndVolumeIsConserved) {
  const Eigen::Vector3d size(0.03, 0.02, 0.01);
  const TetMesh tets = makeBlockMesh(size, {3, 2, 1});
  const SpringMesh mesh = buildSpringMesh(tets, 1060.0);
  // Kuhn grid edges: axis edges, one diagonal per face, one per cell.
  const int nx = 3, ny = 2, nz = 1;
  const int axisEdges =
      nx * (ny + 1) * (nz + 1) + ny * (nx + 1) * (nz + 1) + nz * (nx + 1) * (ny + 1);
  const int faceDiagonals = nx * ny * (nz + 1) + ny * nz * (nx + 1) + nz * nx * (ny + 1);
  EXPECT_EQ(mesh.springCount(), axisEdges + faceDiagonals + nx * ny * nz);
  EXPECT_NEAR(mesh.volume_m3.sum(), size.prod(), 1e-15);
  EXPECT_NEAR(mesh.nodeMass_kg.sum(), 1060.0 * size.prod(), 1e-12);
  EXPECT_TRUE((mesh.restLength_m.array() > 0).all());
}

TEST(SpringMesh, RefusesInvertedAndFlatTets) {
  TetMesh mesh = makeBlockMesh({1, 1, 1}, {1, 1, 1});
  std::swap(mesh.tets(2, 4), mesh.tets(3, 4));
  try {
    buildSpringMesh(mesh, 1000.0);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("tet 4 is inverted"), std::string::npos)
        << error.what();
  }
  TetMesh flat = makeBlockMesh({1, 1, 1}, {1, 1, 1});
  flat.nodes_m.row(2).setZero();
  EXPECT_THROW(buildSpringMesh(flat, 1000.0), std::invalid_argument);
  EXPECT_THROW(buildSpringMesh(makeBlockMesh({1, 1, 1}, {1, 1, 1}), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
