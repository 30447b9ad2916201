// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeCells.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <string>

#include "mesh/BlockMesher.h"
#include "mesh/TetMesh.h"
#include "mesh/TetMeshFile.h"
#include "springs/SpringMesh.h"
#include "springs/VolumeForceField.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

TEST(VolumeCells, ALatticeGroupsIntoItsCubes) {
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({3 * h, 2 * h, h}, {3, 2, 1}), 1000.0);
  const VolumeCells cells =
      groupTetsIntoCells(mesh.restPositions_m, mesh.tets, mesh.tetRestVolume_m3);
  ASSERT_EQ(cells.cellCount(), 6);
  ASSERT_EQ(cells.tets.size(), static_cast<std::size_t>(mesh.tets.cols()));
  std::set<int> seen;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    EXPECT_EQ(cells.nodeCount[static_cast<std::size_t>(c)], 8);
    EXPECT_NEAR(cells.restVolume_m3[c], h * h * h, 1e-12 * h * h * h);
    const int begin = cells.tetStart[static_cast<std::size_t>(c)];
    const int end = cells.tetStart[static_cast<std::size_t>(c) + 1];
    EXPECT_EQ(end - begin, 6);
    // Every tet of a cell lies in one cube (found from its centroid), and its slots name its
    // own nodes.
    const int first = cells.tets[static_cast<std::size_t>(begin)];
    for (int k = begin; k < end; ++k) {
      const int t = cells.tets[static_cast<std::size_t>(k)];
      EXPECT_TRUE(seen.insert(t).second) << "tet " << t << " in two cells";
      EXPECT_EQ(test::cubeOfTet(mesh, t, h), test::cubeOfTet(mesh, first, h));
      for (int i = 0; i < 4; ++i) EXPECT_EQ(cells.nodes(cells.tetSlots(i, t), c), mesh.tets(i, t));
    }
  }
  // A cube's 8 nodes make 28 pairs; neighbouring cubes share theirs on the common face.
  const Eigen::Matrix2Xi pairs = cells.nodePairs();
  std::set<std::pair<int, int>> unique;
  for (Eigen::Index p = 0; p < pairs.cols(); ++p) {
    EXPECT_LT(pairs(0, p), pairs(1, p));
    unique.insert({pairs(0, p), pairs(1, p)});
  }
  EXPECT_EQ(unique.size(), static_cast<std::size_t>(pairs.cols()));
  // All pairs within one cube, counted once.
  std::set<std::pair<int, int>> expected;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    for (int i = 0; i < 8; ++i) {
      for (int j = i + 1; j < 8; ++j) {
        expected.insert({std::min(cells.nodes(i, c), cells.nodes(j, c)),
                         std::max(cells.nodes(i, c), cells.nodes(j, c))});
      }
    }
  }
  EXPECT_EQ(unique, expected);
}

// Signed volume of the k-th tet of cube c as the cube's order around its diagonal gives it.
double volumeAroundTheDiagonal(const VolumeCells& cells, const Eigen::Matrix3Xd& x, Eigen::Index c,
                               int k) {
  const auto at = [&](int row) -> Eigen::Vector3d {
    return x.col(cells.nodes(cells.cubeSlots(row, c), c));
  };
  const Eigen::Vector3d low = at(0);
  return (at(7) - low).dot((at(k + 1) - low).cross(at((k + 1) % 6 + 1) - low)) / 6.0;
}

TEST(VolumeCells, ALatticeCubeIsOrderedAroundItsDiagonal) {
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({3 * h, 2 * h, h}, {3, 2, 1}), 1000.0);
  const VolumeCells cells =
      groupTetsIntoCells(mesh.restPositions_m, mesh.tets, mesh.tetRestVolume_m3);
  // Moved well away from the lattice, one corner through its cube's diagonal: some tets inside
  // out, and the order (fixed at rest) still gives each tet's own signed volume.
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> move(-0.3 * h, 0.3 * h);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += move(random);
  x.col(cells.nodes(cells.cubeSlots(1, 0), 0)) = x.col(cells.nodes(cells.cubeSlots(7, 0), 0));
  int inverted = 0;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    ASSERT_TRUE(cells.isCube(c)) << "cell " << c;
    std::set<int> slots;
    for (int row = 0; row < 8; ++row) slots.insert(cells.cubeSlots(row, c));
    EXPECT_EQ(slots.size(), 8u);
    const Eigen::Vector3d low = mesh.restPositions_m.col(cells.nodes(cells.cubeSlots(0, c), c));
    const Eigen::Vector3d high = mesh.restPositions_m.col(cells.nodes(cells.cubeSlots(7, c), c));
    EXPECT_TRUE(high.isApprox(low + Eigen::Vector3d(h, h, h), 1e-12));
    for (int k = 0; k < 6; ++k) {
      const int t =
          cells.tets[static_cast<std::size_t>(cells.tetStart[static_cast<std::size_t>(c)] + k)];
      const double own = signedTetVolume(x, mesh.tets, t);
      EXPECT_NEAR(volumeAroundTheDiagonal(cells, x, c, k), own, 1e-12 * h * h * h);
      inverted += own <= 0.0 ? 1 : 0;
    }
  }
  EXPECT_GE(inverted, 1);
}

TEST(VolumeCells, EveryCubeOfTheBundledLiverIsOrderedAroundItsDiagonal) {
  const SpringMesh mesh = buildSpringMesh(
      readTetMesh(std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-5300.msh"), 1000.0);
  const VolumeCells cells =
      groupTetsIntoCells(mesh.restPositions_m, mesh.tets, mesh.tetRestVolume_m3);
  ASSERT_GT(cells.cellCount(), 500);
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    ASSERT_TRUE(cells.isCube(c)) << "cell " << c;
    for (int k = 0; k < 6; ++k) {
      const int t =
          cells.tets[static_cast<std::size_t>(cells.tetStart[static_cast<std::size_t>(c)] + k)];
      const double own = signedTetVolume(mesh.restPositions_m, mesh.tets, t);
      EXPECT_NEAR(volumeAroundTheDiagonal(cells, mesh.restPositions_m, c, k), own, 1e-12 * own);
    }
  }
}

TEST(VolumeCells, AnUnstructuredMeshKeepsATermPerTet) {
  // The same lattice with its nodes jiggled: no tet has nodes at both of its bounding box's
  // extreme corners any more.
  TetMesh lattice = makeBlockMesh({0.02, 0.02, 0.02}, {2, 2, 2});
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jiggle(-5e-4, 5e-4);
  for (Eigen::Index i = 0; i < lattice.nodes_m.size(); ++i)
    lattice.nodes_m.data()[i] += jiggle(random);
  const SpringMesh mesh = buildSpringMesh(lattice, 1000.0);
  const VolumeCells cells =
      groupTetsIntoCells(mesh.restPositions_m, mesh.tets, mesh.tetRestVolume_m3);
  ASSERT_EQ(cells.cellCount(), mesh.tets.cols());
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    EXPECT_EQ(cells.nodeCount[static_cast<std::size_t>(c)], 4);
    EXPECT_FALSE(cells.isCube(c));
    const int t = cells.tets[static_cast<std::size_t>(cells.tetStart[static_cast<std::size_t>(c)])];
    EXPECT_EQ(cells.restVolume_m3[c], mesh.tetRestVolume_m3[t]);
  }
}

TEST(VolumeCells, ACubeWithATetTurnedInsideOutIsPushedBack) {
  // Corner (h, 0, 0) of one cube pushed through the cube's main diagonal: its two tets turn
  // inside out, the cube loses volume, and the term pushes the corner back out.
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({h, h, h}, {1, 1, 1}), 1000.0);
  const VolumeForceField field(mesh, 1e5);
  ASSERT_EQ(field.cells().cellCount(), 1);
  int corner = -1;
  for (Eigen::Index j = 0; j < mesh.nodeCount(); ++j) {
    if ((mesh.restPositions_m.col(j) - Eigen::Vector3d(h, 0, 0)).norm() < 1e-12)
      corner = static_cast<int>(j);
  }
  ASSERT_GE(corner, 0);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.col(corner) = Eigen::Vector3d(0.2 * h, 0.8 * h, 0.8 * h);
  ASSERT_GE(VolumeForceField::inspect(mesh, x).invertedTetCount, 1);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  const VolumeFieldReport report = field.addForces(x, f, nullptr);
  EXPECT_GE(report.invertedTetCount, 1);
  EXPECT_LT(report.minVolumeRatio, 0.9);
  const Eigen::Vector3d back = mesh.restPositions_m.col(corner) - x.col(corner);
  EXPECT_GT(f.col(corner).dot(back), 0.0);
}

}  // namespace
}  // namespace tissuesim
