// SPDX-License-Identifier: Apache-2.0
#include "mesh/SurfaceEmbedding.h"

#include <gtest/gtest.h>

#include "mesh/LatticeMesher.h"
#include "mesh/SurfaceReader.h"
#include "mesh/TetMeshFile.h"

namespace tissuesim {
namespace {

class SurfaceEmbeddingTest : public ::testing::Test {
 protected:
  TriangleSurface m_surface =
      readSurface(std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-smooth.obj", {0.03, ""});
  TetMesh m_mesh = readTetMesh(std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-1000.msh");
  SurfaceEmbedding m_embedding{m_mesh, m_surface.vertices_m};
};

TEST_F(SurfaceEmbeddingTest, RestPositionsAreReproduced) {
  Eigen::Matrix3Xd surface(3, m_surface.vertexCount());
  m_embedding.apply(m_mesh.nodes_m, surface);
  EXPECT_LT((surface - m_surface.vertices_m).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(m_embedding.weights().colwise().sum().maxCoeff(), 1.0, 1e-12);
  // The lattice keeps cubes with centres inside, so some vertices lie just outside: tied to
  // the nearest tet, within one cube of it.
  EXPECT_LT(m_embedding.maxOutsideDistance_m(), 0.03);
}

TEST_F(SurfaceEmbeddingTest, RigidMotionMovesTheSurfaceRigidly) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d translation(0.1, -0.2, 0.05);
  const Eigen::Matrix3Xd moved = (rotation * m_mesh.nodes_m).colwise() + translation;
  Eigen::Matrix3Xd surface(3, m_surface.vertexCount());
  m_embedding.apply(moved, surface);
  const Eigen::Matrix3Xd expected = (rotation * m_surface.vertices_m).colwise() + translation;
  EXPECT_LT((surface - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_F(SurfaceEmbeddingTest, AffineStretchIsReproducedExactly) {
  Eigen::Matrix3d stretch;
  stretch << 1.3, 0.2, 0.0, 0.0, 0.8, 0.1, 0.05, 0.0, 1.1;
  Eigen::Matrix3Xd surface(3, m_surface.vertexCount());
  m_embedding.apply(stretch * m_mesh.nodes_m, surface);
  EXPECT_LT((surface - stretch * m_surface.vertices_m).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace tissuesim
