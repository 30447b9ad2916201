// SPDX-License-Identifier: Apache-2.0
#include "render/VtkMeshFiles.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataSet.h>
#include <vtkGenericDataObjectReader.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <utility>
#include <vector>

#include "mesh/IsolatedMeshRead.h"
#include "mesh/SurfaceReader.h"

namespace tissuesim {
namespace {

/// VTK prints its complaints to stderr; ours is one line. Silence it while reading.
class QuietVtk {
 public:
  QuietVtk() : m_previous(vtkObject::GetGlobalWarningDisplay()) {
    vtkObject::GlobalWarningDisplayOff();
  }
  ~QuietVtk() { vtkObject::SetGlobalWarningDisplay(m_previous); }
  QuietVtk(const QuietVtk&) = delete;
  QuietVtk& operator=(const QuietVtk&) = delete;

 private:
  int m_previous;
};

void checkFile(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw MeshFileError(path.string() + ": cannot open the mesh file (missing or not a file)");
  }
  const auto size = std::filesystem::file_size(path, error);
  if (!error && size == 0) throw MeshFileError(path.string() + ": the file is empty");
  if (!error && size > kMaxMeshFileBytes) {
    throw MeshFileError(path.string() + ": beyond the limit of 256 MiB for a mesh file");
  }
}

/// Reads any of the VTK formats into a dataset, or throws.
vtkSmartPointer<vtkDataSet> readDataSet(const std::filesystem::path& path) {
  checkFile(path);
  const QuietVtk quiet;
  const std::string name = path.string();
  const std::string extension = path.extension().string();
  vtkSmartPointer<vtkDataSet> data;
  if (extension == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    if (reader->CanReadFile(name.c_str()) == 0)
      throw MeshFileError(name + ": not a VTK XML polydata file");
    reader->SetFileName(name.c_str());
    reader->Update();
    data = reader->GetOutput();
  } else if (extension == ".vtu") {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    if (reader->CanReadFile(name.c_str()) == 0)
      throw MeshFileError(name + ": not a VTK XML unstructured grid file");
    reader->SetFileName(name.c_str());
    reader->Update();
    data = reader->GetOutput();
  } else {
    vtkNew<vtkGenericDataObjectReader> reader;
    reader->SetFileName(name.c_str());
    if (reader->OpenVTKFile() == 0 || reader->ReadHeader() == 0) {
      reader->CloseVTKFile();
      throw MeshFileError(name + ": not a legacy VTK file (no '# vtk DataFile' header)");
    }
    reader->CloseVTKFile();
    reader->Update();
    data = vtkDataSet::SafeDownCast(reader->GetOutput());
  }
  if (data == nullptr || data->GetNumberOfPoints() == 0) {
    throw MeshFileError(name + ": the VTK file holds no points (unreadable or empty dataset)");
  }
  return data;
}

Eigen::Matrix3Xd points(vtkDataSet* data, const std::string& name, double metresPerUnit) {
  Eigen::Matrix3Xd nodes(3, data->GetNumberOfPoints());
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    double p[3];
    data->GetPoint(i, p);
    nodes.col(i) = Eigen::Vector3d(p[0], p[1], p[2]) * metresPerUnit;
    if (!nodes.col(i).allFinite()) {
      throw MeshFileError(name + ": point " + std::to_string(i) +
                          " has a coordinate that is not finite");
    }
    if (nodes.col(i).cwiseAbs().maxCoeff() > 100.0) {
      throw MeshFileError(name + ": point " + std::to_string(i) +
                          " lies beyond 100 m from the origin after scaling (check the units)");
    }
  }
  return nodes;
}

/// VTK passes a cell's point ids through as the file has them: each must name a point.
void checkPointIds(vtkIdList* ids, vtkIdType pointCount, const std::string& name, vtkIdType cell) {
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
    const vtkIdType id = ids->GetId(k);
    if (id < 0 || id >= pointCount) {
      throw MeshFileError(name + ": cell " + std::to_string(cell) + " refers to point " +
                          std::to_string(id) + ", but the file has " + std::to_string(pointCount) +
                          " points");
    }
  }
}

/// The reading itself, run in the isolated child (the VTK readers see the file there only).
TriangleSurface importVtkSurface(const std::filesystem::path& path, double metresPerUnit) {
  const std::string name = path.string();
  const vtkSmartPointer<vtkDataSet> data = readDataSet(path);
  TriangleSurface surface;
  surface.vertices_m = points(data, name, metresPerUnit);
  std::vector<Eigen::Vector3i> triangles;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
    const int type = data->GetCellType(c);
    if (type != VTK_TRIANGLE && type != VTK_POLYGON && type != VTK_QUAD) continue;
    data->GetCellPoints(c, ids);
    checkPointIds(ids, data->GetNumberOfPoints(), name, c);
    for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k) {
      triangles.emplace_back(static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(k)),
                             static_cast<int>(ids->GetId(k + 1)));
    }
  }
  if (triangles.empty()) throw MeshFileError(name + ": the VTK file holds no polygons");
  surface.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t f = 0; f < triangles.size(); ++f)
    surface.triangles.col(static_cast<Eigen::Index>(f)) = triangles[f];
  return surface;
}

ReadTetMesh importVtkTetMesh(const std::filesystem::path& path, double metresPerUnit) {
  const std::string name = path.string();
  const vtkSmartPointer<vtkDataSet> data = readDataSet(path);
  ReadTetMesh result;
  TetMesh& mesh = result.mesh;
  mesh.nodes_m = points(data, name, metresPerUnit);
  std::vector<Eigen::Vector4i> tets;
  int skipped = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
    if (data->GetCellType(c) != VTK_TETRA) {
      ++skipped;
      continue;
    }
    data->GetCellPoints(c, ids);
    checkPointIds(ids, data->GetNumberOfPoints(), name, c);
    if (ids->GetNumberOfIds() != 4) {
      throw MeshFileError(name + ": tetrahedron " + std::to_string(c) + " has " +
                          std::to_string(ids->GetNumberOfIds()) + " points, not 4");
    }
    tets.emplace_back(static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                      static_cast<int>(ids->GetId(2)), static_cast<int>(ids->GetId(3)));
  }
  if (tets.empty()) {
    throw MeshFileError(name + ": the mesh has no tetrahedra (" + std::to_string(skipped) +
                        " other cells)");
  }
  mesh.tets.resize(4, static_cast<Eigen::Index>(tets.size()));
  for (std::size_t t = 0; t < tets.size(); ++t)
    mesh.tets.col(static_cast<Eigen::Index>(t)) = tets[t];
  result.skippedElements = skipped;
  return result;
}

}  // namespace

bool isVtkMeshFile(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".vtk" || extension == ".vtp" || extension == ".vtu";
}

TriangleSurface readVtkSurface(const std::filesystem::path& path, double metresPerUnit) {
  checkFile(path);
  return readSurfaceIsolated(path, [&] { return importVtkSurface(path, metresPerUnit); });
}

TetMesh readVtkTetMesh(const std::filesystem::path& path, double metresPerUnit,
                       TetMeshReadReport* report) {
  checkFile(path);
  ReadTetMesh read =
      readTetMeshIsolated(path, [&] { return importVtkTetMesh(path, metresPerUnit); });
  TetMeshReadReport local;
  local.skippedElements = read.skippedElements;
  local.format = path.extension() == ".vtu" ? "vtk xml" : "vtk legacy";
  checkTetOrientation(read.mesh, path.string(), &local);
  if (report != nullptr) *report = local;
  return std::move(read.mesh);
}

}  // namespace tissuesim
