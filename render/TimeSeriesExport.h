// SPDX-License-Identifier: Apache-2.0
#pragma once
// A simulation written for inspection in ParaView: at each call of write(), the drawn surface
// (VTK XML polydata, .vtp) and the tet mesh (VTK XML unstructured grid, .vtu) at the given
// positions, and a ParaView collection (.pvd) that lists every frame with its time, rewritten
// after each frame so that it is complete whenever the run stops.
//
// Point data on both: "displacement" (m, 3 components, from the mesh's unloaded shape) and
// "stretch" (the window's colour map: per tet node, the incident spring's stretch farthest
// from 1; interpolated onto the drawn surface by its embedding weights). Without a drawn
// surface the tet mesh's boundary is written as the surface.
//
// Files: FOLDER/surface_NNNNNN.vtp, FOLDER/tets_NNNNNN.vtu, FOLDER/series.pvd. Each is written
// to a temporary name and renamed, so no half-written file is left behind.

#include <filesystem>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

#include "sim/SceneGeometry.h"
#include "springs/SpringMesh.h"

class vtkPolyData;
class vtkUnstructuredGrid;

namespace tissuesim {

class TimeSeriesExport {
 public:
  /// Creates `folder` if needed. Geometry and springs must outlive this object.
  /// @throws std::runtime_error naming the folder when it cannot be created or written.
  TimeSeriesExport(const std::filesystem::path& folder, const SceneGeometry& geometry,
                   const SpringMesh& springs);
  ~TimeSeriesExport();
  TimeSeriesExport(const TimeSeriesExport&) = delete;
  TimeSeriesExport& operator=(const TimeSeriesExport&) = delete;

  /// Writes one frame: tet-node positions x (3 by #V, m) at time_s.
  /// @throws std::runtime_error naming the file that could not be written.
  void write(double time_s, const Eigen::Matrix3Xd& x);

  int frameCount() const { return static_cast<int>(m_times.size()); }
  const std::filesystem::path& collectionPath() const { return m_collection; }

 private:
  void writeCollection() const;
  /// The tet mesh's grid (m_tets) from the geometry's mesh as it is now.
  void buildTetGrid();

  std::filesystem::path m_folder;
  std::filesystem::path m_collection;
  const SceneGeometry& m_geometry;
  const SpringMesh& m_springs;
  Eigen::Matrix3Xi m_surfaceTriangles;
  Eigen::Matrix3Xd m_surfaceRest_m;
  vtkSmartPointer<vtkPolyData> m_surface;
  vtkSmartPointer<vtkUnstructuredGrid> m_tets;
  Eigen::VectorXd m_nodeStretch;     ///< per tet node, each frame
  Eigen::VectorXd m_surfaceStretch;  ///< per drawn vertex, each frame
  Eigen::Matrix3Xd m_surfaceX;
  std::vector<double> m_times;
};

}  // namespace tissuesim
