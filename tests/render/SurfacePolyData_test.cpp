// SPDX-License-Identifier: Apache-2.0
#include "render/SurfacePolyData.h"

#include <stdexcept>

#include <gtest/gtest.h>
#include <vtkPolyData.h>

namespace tissuesim {
namespace {

TEST(SurfacePolyData, CopiesTopologyAndUpdatesPointsInPlace) {
  Eigen::MatrixX3d v(4, 3);
  v << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Eigen::MatrixX3i f(4, 3);
  f << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  SurfacePolyData surface(v, f);
  vtkPolyData* poly = surface.polyData();
  EXPECT_EQ(poly->GetNumberOfPoints(), 4);
  EXPECT_EQ(poly->GetNumberOfPolys(), 4);
  double bounds[6];
  poly->GetBounds(bounds);
  EXPECT_DOUBLE_EQ(bounds[1], 1.0);

  const vtkMTimeType before = poly->GetPoints()->GetMTime();
  Eigen::MatrixX3d moved = v * 2.0;
  surface.updatePoints(moved);
  EXPECT_GT(poly->GetPoints()->GetMTime(), before);
  poly->ComputeBounds();
  poly->GetBounds(bounds);
  EXPECT_DOUBLE_EQ(bounds[1], 2.0);
  EXPECT_DOUBLE_EQ(bounds[5], 2.0);
}

TEST(SurfacePolyData, RejectsBadInput) {
  Eigen::MatrixX3d v = Eigen::MatrixX3d::Zero(3, 3);
  Eigen::MatrixX3i f(1, 3);
  f << 0, 1, 3;
  EXPECT_THROW(SurfacePolyData(v, f), std::invalid_argument);
  f << 0, 1, 2;
  SurfacePolyData surface(v, f);
  EXPECT_THROW(surface.updatePoints(Eigen::MatrixX3d::Zero(4, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
