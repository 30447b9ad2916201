// SPDX-License-Identifier: Apache-2.0
#pragma once
// A vtkPolyData view of a triangle surface whose vertices move: the topology is copied once,
// and each frame only the points are overwritten in place (no reallocation), then marked
// modified so VTK's pipeline re-renders.

#include <vtkSmartPointer.h>
#include <Eigen/Core>

class vtkPolyData;

namespace tissuesim {

class SurfacePolyData {
 public:
  /// @param vertices #V by 3 positions (m); @param triangles #F by 3 vertex indices.
  /// @throws std::invalid_argument for indices outside the vertex range.
  SurfacePolyData(const Eigen::Ref<const Eigen::MatrixX3d>& vertices,
                  const Eigen::Ref<const Eigen::MatrixX3i>& triangles);

  /// Overwrites the points (same count and order as at construction).
  void updatePoints(const Eigen::Ref<const Eigen::MatrixX3d>& vertices);

  vtkPolyData* polyData() const { return m_polyData; }

 private:
  vtkSmartPointer<vtkPolyData> m_polyData;
};

}  // namespace tissuesim
