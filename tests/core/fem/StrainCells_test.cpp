// SPDX-License-Identifier: Apache-2.0
// The smoothing cells per face and per node: one per face (4 or 5 nodes) or per node in a tet,
// their volumes adding up to the mesh's, and each cell's F exact for any affine motion (its
// gradients sum to zero and reproduce the identity at rest).

#include "fem/StrainCells.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "mesh/TetMesh.h"
#include "mesh/TetMeshFile.h"
#include "support/TestMeshes.h"

namespace tissuesim {
namespace {

/// The cells' volumes add up to the mesh's, and each cell's F is exact for an affine motion.
void expectWholeAndAffineExact(const StrainCells& cells, const TetMesh& mesh) {
  double total = 0.0;
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    total += signedTetVolume(mesh.nodes_m, mesh.tets, t);
  }
  EXPECT_NEAR(cells.volume_m3.sum(), total, 1e-12 * total);
  const Eigen::Matrix3Xd& rest = mesh.nodes_m;
  Eigen::Matrix3d a;
  a << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.05;
  const Eigen::Vector3d shift(0.3, -0.1, 0.2);
  const Eigen::Matrix3Xd x = (a * rest).colwise() + shift;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    Eigen::Matrix3d f = Eigen::Matrix3d::Zero();
    for (int e = cells.start[static_cast<std::size_t>(c)];
         e < cells.start[static_cast<std::size_t>(c) + 1]; ++e) {
      f += x.col(cells.nodes[static_cast<std::size_t>(e)]) * cells.gradients_1_m.col(e).transpose();
    }
    EXPECT_LT((f - a).norm(), 1e-9) << "cell " << c;
  }
}

TEST(StrainCells, PerFaceACellForEachFaceOfOneOrTwoTets) {
  const TetMesh mesh = test::unstructuredBlock();
  const StrainCells cells = faceStrainCells(mesh.nodes_m, mesh.tets);
  std::set<std::set<int>> faces;
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    for (int omitted = 0; omitted < 4; ++omitted) {
      std::set<int> face;
      for (int c = 0; c < 4; ++c) {
        if (c != omitted) face.insert(mesh.tets(c, t));
      }
      faces.insert(face);
    }
  }
  ASSERT_EQ(cells.cellCount(), static_cast<Eigen::Index>(faces.size()));
  const Eigen::Index boundary = boundaryFaces(mesh).cols();
  Eigen::Index ofFour = 0;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    const int size =
        cells.start[static_cast<std::size_t>(c) + 1] - cells.start[static_cast<std::size_t>(c)];
    EXPECT_TRUE(size == 4 || size == 5) << size;
    ofFour += size == 4 ? 1 : 0;
  }
  EXPECT_EQ(ofFour, boundary);
  expectWholeAndAffineExact(cells, mesh);
}

TEST(StrainCells, PerNodeACellForEachNodeInATetOverItsStar) {
  const TetMesh mesh = test::unstructuredBlock();
  const StrainCells cells = nodeStrainCells(mesh.nodes_m, mesh.tets);
  const NodeTetIncidence incidence = nodeTetIncidence(mesh.tets, mesh.nodeCount());
  const NodeStars stars = nodeStars(mesh.tets, incidence);
  Eigen::Index inTets = 0;
  std::size_t cell = 0;
  for (std::size_t a = 0; a + 1 < incidence.start.size(); ++a) {
    if (incidence.start[a] == incidence.start[a + 1]) continue;
    ++inTets;
    ASSERT_LT(cell, static_cast<std::size_t>(cells.cellCount()));
    const std::vector<int> star(stars.nodes.begin() + stars.start[a],
                                stars.nodes.begin() + stars.start[a + 1]);
    const std::vector<int> nodes(cells.nodes.begin() + cells.start[cell],
                                 cells.nodes.begin() + cells.start[cell + 1]);
    EXPECT_EQ(nodes, star) << "node " << a;
    ++cell;
  }
  EXPECT_EQ(cells.cellCount(), inTets);
  expectWholeAndAffineExact(cells, mesh);
}

TEST(StrainCells, ATetInsideOutIsRefused) {
  TetMesh mesh = test::unstructuredBlock();
  std::swap(mesh.tets(0, 3), mesh.tets(1, 3));
  EXPECT_THROW(faceStrainCells(mesh.nodes_m, mesh.tets), std::invalid_argument);
  EXPECT_THROW(nodeStrainCells(mesh.nodes_m, mesh.tets), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
