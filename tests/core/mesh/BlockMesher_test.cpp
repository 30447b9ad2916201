// SPDX-License-Identifier: Apache-2.0
#include "mesh/BlockMesher.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(BlockMesher, CountsVolumesAndOrientation) {
  const Eigen::Vector3d size(0.055, 0.02, 0.005);
  const TetMesh mesh = makeBlockMesh(size, {11, 4, 1});
  EXPECT_EQ(mesh.nodeCount(), 12 * 5 * 2);
  EXPECT_EQ(mesh.tetCount(), 6 * 11 * 4 * 1);
  const TetQualityReport report = inspectTets(mesh);
  EXPECT_TRUE(report.invertedTets.empty());
  EXPECT_TRUE(report.slivers.empty());
  EXPECT_NEAR(report.totalVolume_m3, size.prod(), 1e-15);
  EXPECT_GT(report.minVolume_m3, 0.0);
}

TEST(BlockMesher, IsConforming) {
  // Every interior face is shared by two tets, every boundary face belongs to one; a grid of
  // n cells has 2 * 2 * (n_x n_y + n_y n_z + n_z n_x) boundary triangles.
  const TetMesh mesh = makeBlockMesh({1, 1, 1}, {3, 2, 2});
  std::map<std::array<int, 3>, int> faces;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        if (i != skip) face[static_cast<std::size_t>(k++)] = mesh.tets(i, t);
      }
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  }
  int boundary = 0;
  for (const auto& [face, count] : faces) {
    ASSERT_LE(count, 2);
    boundary += count == 1 ? 1 : 0;
  }
  EXPECT_EQ(boundary, 4 * (3 * 2 + 2 * 2 + 2 * 3));
}

TEST(BlockMesher, RejectsBadSizes) {
  EXPECT_THROW(makeBlockMesh({0, 1, 1}, {1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(makeBlockMesh({1, 1, 1}, {1, 0, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
