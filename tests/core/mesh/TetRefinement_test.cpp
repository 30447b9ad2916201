// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetRefinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "mesh/BlockMesher.h"
#include "mesh/SurfaceInspection.h"

namespace tissuesim {
namespace {

double totalVolume(const TetMesh& mesh) { return inspectTets(mesh).totalVolume_m3; }

/// The mesh's boundary as a surface: its area, and whether it is closed (a hanging node would
/// leave a face inside the mesh unmatched, an edge with one face).
TriangleSurface boundarySurface(const TetMesh& mesh) {
  return TriangleSurface{mesh.nodes_m, boundaryFaces(mesh)};
}
double boundaryArea(const TetMesh& mesh) {
  const TriangleSurface boundary = boundarySurface(mesh);
  return vertexAreas(boundary.vertices_m, boundary.triangles).sum();
}
bool isBoundaryClosed(const TetMesh& mesh) {
  return inspectSurface(boundarySurface(mesh)).isClosedManifold();
}

TetMeshGrading blockGrading() {
  TetMeshGrading grading;
  grading.centre_m = Eigen::Vector3d(0.02, 0.02, 0.02);  // the top face's middle
  grading.finest_m = 0.003;
  grading.growth = 0.5;
  grading.coarsest_m = 0.02;
  return grading;
}

TEST(TetRefinement, ARefinedBlockConformsKeepsItsVolumeAndMeetsTheGrading) {
  const TetMesh block = makeBlockMesh(Eigen::Vector3d(0.04, 0.04, 0.02), Eigen::Vector3i(2, 2, 1));
  const TetMeshGrading grading = blockGrading();
  const RefinedTetMesh refined = refineTetMesh(block, grading);
  const TetMesh& mesh = refined.mesh;

  ASSERT_GT(mesh.nodeCount(), 10 * block.nodeCount());
  EXPECT_EQ(refined.splitEdges.cols(), mesh.nodeCount() - block.nodeCount());
  EXPECT_TRUE(mesh.nodes_m.leftCols(block.nodeCount()).isApprox(block.nodes_m, 0.0));
  for (Eigen::Index k = 0; k < refined.splitEdges.cols(); ++k) {
    const Eigen::Index node = block.nodeCount() + k;
    ASSERT_LT(refined.splitEdges(0, k), node);
    ASSERT_LT(refined.splitEdges(1, k), node);
    // With no surface to follow, each new node is its edge's midpoint.
    ASSERT_TRUE(mesh.nodes_m.col(node).isApprox(0.5 * (mesh.nodes_m.col(refined.splitEdges(0, k)) +
                                                       mesh.nodes_m.col(refined.splitEdges(1, k))),
                                                1e-12));
  }
  EXPECT_NEAR(totalVolume(mesh), totalVolume(block), 1e-12 * totalVolume(block));
  EXPECT_NEAR(boundaryArea(mesh), boundaryArea(block), 1e-12 * boundaryArea(block));
  EXPECT_TRUE(isBoundaryClosed(mesh));
  const TetQualityReport before = inspectTets(block);
  const TetQualityReport after = inspectTets(mesh);
  EXPECT_TRUE(after.invertedTets.empty());
  EXPECT_TRUE(after.slivers.empty());
  // Longest-edge bisection degrades the shapes a bounded amount, not without end.
  EXPECT_GT(after.minRadiusRatio, 0.3 * before.minRadiusRatio);

  double finestNearCentre_m = 1.0;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (const auto& edge : {std::pair{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}) {
      const Eigen::Vector3d a = mesh.nodes_m.col(mesh.tets(edge.first, t));
      const Eigen::Vector3d b = mesh.nodes_m.col(mesh.tets(edge.second, t));
      const double size = grading.sizeAt(0.5 * (a + b));
      if (size < grading.coarsest_m) {
        ASSERT_LE((b - a).norm(), size * (1.0 + 1e-12));
      }
      if ((0.5 * (a + b) - grading.centre_m).norm() < 0.003)
        finestNearCentre_m = std::min(finestNearCentre_m, (b - a).norm());
    }
  }
  // Not refined past what the grading asks: the block's 20 mm edges halved down to 2.5 mm.
  EXPECT_GT(finestNearCentre_m, 0.5 * grading.finest_m);
}

TEST(TetRefinement, NewBoundaryNodesLieOnTheDrawnSurface) {
  const TetMesh cube = makeBlockMesh(Eigen::Vector3d(0.02, 0.02, 0.02), Eigen::Vector3i(1, 1, 1));
  // The drawn surface: the cube's boundary grown 5 % about its centre, half a millimetre out.
  TriangleSurface drawn;
  drawn.triangles = boundaryFaces(cube);
  const Eigen::Vector3d centre(0.01, 0.01, 0.01);
  drawn.vertices_m = ((cube.nodes_m.colwise() - centre) * 1.05).colwise() + centre;
  TetMeshGrading grading;
  grading.centre_m = centre;
  grading.finest_m = 0.006;
  grading.growth = 0.0;
  grading.coarsest_m = 0.02;
  const RefinedTetMesh refined = refineTetMesh(cube, grading, &drawn);
  const TetMesh& mesh = refined.mesh;
  ASSERT_GT(mesh.nodeCount(), cube.nodeCount());

  std::vector<char> onBoundary(static_cast<std::size_t>(mesh.nodeCount()), 0);
  for (const int node : faceNodes(boundaryFaces(mesh)))
    onBoundary[static_cast<std::size_t>(node)] = 1;
  int moved = 0;
  for (Eigen::Index node = cube.nodeCount(); node < mesh.nodeCount(); ++node) {
    const Eigen::Vector3d p = mesh.nodes_m.col(node);
    const double outside = ((p - centre).cwiseAbs().array() - 0.0105).maxCoeff();
    if (onBoundary[static_cast<std::size_t>(node)] != 0) {
      // On the grown cube's boundary: its largest offset from the centre is 10.5 mm.
      ASSERT_NEAR(outside, 0.0, 1e-12) << "node " << node;
      ++moved;
    } else {
      ASSERT_LT(outside, -1e-4) << "node " << node;
    }
  }
  EXPECT_GT(moved, 0);
  EXPECT_TRUE(inspectTets(mesh).invertedTets.empty());
  EXPECT_TRUE(isBoundaryClosed(mesh));
  EXPECT_GT(totalVolume(mesh), totalVolume(cube));
  EXPECT_LT(totalVolume(mesh), std::pow(0.021, 3));
}

TEST(TetRefinement, AGradingAlreadyMetLeavesTheMeshAsItIsAndRefiningIsRepeatable) {
  const TetMesh block = makeBlockMesh(Eigen::Vector3d(0.04, 0.04, 0.02), Eigen::Vector3i(2, 2, 1));
  TetMeshGrading loose = blockGrading();
  loose.finest_m = 0.05;
  loose.coarsest_m = 0.1;
  const RefinedTetMesh same = refineTetMesh(block, loose);
  EXPECT_EQ(same.splitEdges.cols(), 0);
  EXPECT_EQ(same.mesh.tets, block.tets);

  const RefinedTetMesh first = refineTetMesh(block, blockGrading());
  const RefinedTetMesh second = refineTetMesh(block, blockGrading());
  EXPECT_EQ(first.mesh.tets, second.mesh.tets);
  EXPECT_EQ(first.mesh.nodes_m, second.mesh.nodes_m);
}

TEST(TetRefinement, ItRefusesAGradingOutOfRangeAndAnInvertedTet) {
  const TetMesh block = makeBlockMesh(Eigen::Vector3d(0.04, 0.04, 0.02), Eigen::Vector3i(2, 2, 1));
  TetMeshGrading grading = blockGrading();
  grading.finest_m = 0.0;
  EXPECT_THROW(refineTetMesh(block, grading), std::invalid_argument);
  grading = blockGrading();
  grading.coarsest_m = 0.001;
  EXPECT_THROW(refineTetMesh(block, grading), std::invalid_argument);
  grading = blockGrading();
  grading.growth = -1.0;
  EXPECT_THROW(refineTetMesh(block, grading), std::invalid_argument);
  grading = blockGrading();
  grading.finest_m = 1e-5;  // 10 micrometres everywhere: billions of tets
  grading.growth = 0.0;
  try {
    refineTetMesh(block, grading);
    ADD_FAILURE() << "a refinement past the limit was made";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("would pass 300000 tets"), std::string::npos)
        << error.what();
  }
  TetMesh inverted = block;
  std::swap(inverted.tets(0, 3), inverted.tets(1, 3));
  EXPECT_THROW(refineTetMesh(inverted, blockGrading()), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
