// SPDX-License-Identifier: Apache-2.0
// The FEM at its own rate (fem/HapticRateFem.h): each update's contact reaches as far out as the
// probe's pace since the last update carries it, and no further than the largest margin.

#include "fem/HapticRateFem.h"

#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "fem/SampledSurface.h"
#include "mesh/BlockMesher.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kRadius_m = 0.0025;

/// A 30 x 30 x 10 mm block of quadratic tets, its bottom held, its surface sampled every 0.5 mm,
/// and a probe pointing down at it; the FEM at its own rate on it with a margin of its own.
struct PokedBlock {
  TetMesh linear = makeBlockMesh({0.03, 0.03, 0.01}, {6, 6, 2});
  QuadraticTetMesh mesh = makeQuadraticTetMesh(linear);
  FemModel model{mesh, test::liverEnergy(), 50.0 * test::liverEnergy().initialShearModulus()};
  std::unique_ptr<HapticRateFem> fem;

  explicit PokedBlock(double margin_m) {
    std::vector<char> isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
    for (Eigen::Index v = 0; v < mesh.nodeCount(); ++v) {
      if (mesh.nodes_m(2, v) < 1e-9) std::fill_n(isFixed.begin() + 3 * v, 3, char{1});
    }
    fem = std::make_unique<HapticRateFem>(
        model, isFixed,
        sampleSurfacePoints(mesh, quadraticSurfacePieces(linear, mesh), 0.0005, 1e11,
                            Eigen::Vector3d::Zero(), std::numeric_limits<double>::infinity()),
        margin_m, 1);
  }

  /// The probe's hemisphere centred over (x, y), its lowest point 0.1 mm above the top face.
  static Eigen::Vector3d tip(double x_m, double y_m) {
    return {x_m, y_m, 0.01 + 0.0001 + kRadius_m};
  }
  static Eigen::Vector3d top(const Eigen::Vector3d& tip_m) {
    return tip_m + Eigen::Vector3d(0.0, 0.0, 0.05);
  }
  HapticRateUpdate settle(const Eigen::Vector3d& tip_m) {
    CondensedCapsuleContact contact;
    return fem->settle(tip_m, top(tip_m), kRadius_m, contact);
  }
  /// An update with no load on the body, the probe at tip_m.
  HapticRateUpdate update(const Eigen::Vector3d& tip_m) {
    CondensedCapsuleContact next;
    return fem->update(nullptr, {}, Eigen::Matrix3Xd(3, 0), tip_m, top(tip_m), kRadius_m, next);
  }
};

TEST(HapticRateFem, TheContactReachesAsFarAsTheProbesPaceCarriesIt) {
  // The probe moved 0.3 mm along the face between two updates: the contact at the second takes
  // the points within 0.3 + 2 x 0.3 mm, as a contact with a 0.9 mm margin does there; held still
  // there, 0.3 mm again. Put 5 mm away, it takes no more than the largest margin's.
  const Eigen::Vector3d start = PokedBlock::tip(0.015, 0.015);
  const Eigen::Vector3d moved = PokedBlock::tip(0.0153, 0.015);
  const Eigen::Vector3d away = PokedBlock::tip(0.0103, 0.015);
  PokedBlock block(0.0003);
  ASSERT_TRUE(block.settle(start).hasNext);
  const HapticRateUpdate moving = block.update(moved);
  const HapticRateUpdate still = block.update(moved);
  const HapticRateUpdate putAway = block.update(away);
  ASSERT_TRUE(moving.hasNext && still.hasNext && putAway.hasNext);

  PokedBlock wider(0.0009);
  ASSERT_TRUE(wider.settle(moved).hasNext);
  EXPECT_EQ(moving.points, wider.update(moved).points);
  PokedBlock narrow(0.0003);
  ASSERT_TRUE(narrow.settle(moved).hasNext);
  EXPECT_EQ(still.points, narrow.update(moved).points);
  EXPECT_GT(moving.points, still.points);
  EXPECT_GT(still.points, 0);

  PokedBlock largest(HapticRateFem::kLargestCandidateMargin_m);
  ASSERT_TRUE(largest.settle(away).hasNext);
  EXPECT_EQ(putAway.points, largest.update(away).points);
}

}  // namespace
}  // namespace tissuesim
