// SPDX-License-Identifier: Apache-2.0
#include "render/SurfacePolyData.h"

#include <stdexcept>
#include <string>

#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

namespace tissuesim {

SurfacePolyData::SurfacePolyData(const Eigen::Ref<const Eigen::MatrixX3d>& vertices,
                                 const Eigen::Ref<const Eigen::MatrixX3i>& triangles)
    : m_polyData(vtkSmartPointer<vtkPolyData>::New()) {
  if (triangles.rows() > 0 &&
      (triangles.minCoeff() < 0 || triangles.maxCoeff() >= vertices.rows())) {
    throw std::invalid_argument("a surface triangle refers to a vertex outside 0.." +
                                std::to_string(vertices.rows() - 1));
  }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vertices.rows());
  m_polyData->SetPoints(points);
  updatePoints(vertices);

  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->AllocateExact(triangles.rows(), 3 * triangles.rows());
  for (Eigen::Index i = 0; i < triangles.rows(); ++i) {
    const vtkIdType ids[3] = {triangles(i, 0), triangles(i, 1), triangles(i, 2)};
    cells->InsertNextCell(3, ids);
  }
  m_polyData->SetPolys(cells);
}

void SurfacePolyData::updatePoints(const Eigen::Ref<const Eigen::MatrixX3d>& vertices) {
  vtkPoints* points = m_polyData->GetPoints();
  if (vertices.rows() != points->GetNumberOfPoints()) {
    throw std::invalid_argument("updatePoints needs " +
                                std::to_string(points->GetNumberOfPoints()) + " vertices, got " +
                                std::to_string(vertices.rows()));
  }
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) {
    points->SetPoint(i, vertices(i, 0), vertices(i, 1), vertices(i, 2));
  }
  points->Modified();
}

}  // namespace tissuesim
