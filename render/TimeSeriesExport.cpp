// SPDX-License-Identifier: Apache-2.0
#include "render/TimeSeriesExport.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "io/WholeFile.h"
#include "mesh/TetMesh.h"
#include "springs/NodeStretch.h"

namespace tissuesim {
namespace {

vtkSmartPointer<vtkPoints> makePoints(Eigen::Index count) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  return points;
}

vtkSmartPointer<vtkDoubleArray> makeArray(const char* name, int components, Eigen::Index count) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(count);
  return array;
}

/// Positions into a dataset's points and "displacement" (from rest) and "stretch" into its point
/// data.
void setFrame(vtkPointSet* data, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& rest,
              const Eigen::VectorXd& stretch) {
  vtkPoints* points = data->GetPoints();
  auto* displacement = vtkDoubleArray::SafeDownCast(data->GetPointData()->GetArray("displacement"));
  auto* value = vtkDoubleArray::SafeDownCast(data->GetPointData()->GetArray("stretch"));
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    points->SetPoint(i, x(0, i), x(1, i), x(2, i));
    const Eigen::Vector3d d = x.col(i) - rest.col(i);
    displacement->SetTuple3(i, d.x(), d.y(), d.z());
    value->SetValue(i, stretch[i]);
  }
  points->Modified();
  data->Modified();
}

void addFrameArrays(vtkPointSet* data, Eigen::Index count) {
  data->GetPointData()->AddArray(makeArray("displacement", 3, count));
  auto stretch = makeArray("stretch", 1, count);
  data->GetPointData()->AddArray(stretch);
  data->GetPointData()->SetActiveScalars("stretch");
}

/// A VTK XML writer's file, whole or not at all (io/WholeFile.h).
template <typename Writer>
void writeAtomically(Writer* writer, const std::filesystem::path& path) {
  writer->SetDataModeToBinary();
  writeWholeFileWith(path, [&](const std::filesystem::path& partial) {
    writer->SetFileName(partial.c_str());
    return writer->Write() == 1;
  });
}

std::string frameName(const char* stem, std::size_t frame, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06zu.%s", stem, frame, extension);
  return name;
}

}  // namespace

TimeSeriesExport::TimeSeriesExport(const std::filesystem::path& folder,
                                   const SceneGeometry& geometry, const SpringMesh& springs)
    : m_folder(folder),
      m_collection(folder / "series.pvd"),
      m_geometry(geometry),
      m_springs(springs),
      m_surface(vtkSmartPointer<vtkPolyData>::New()),
      m_tets(vtkSmartPointer<vtkUnstructuredGrid>::New()) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error || !std::filesystem::is_directory(folder)) {
    throw std::runtime_error("cannot create the export folder " + folder.string() +
                             (error ? " (" + error.message() + ")" : ""));
  }
  const bool isEmbedded = geometry.surface && geometry.embedding;
  if (isEmbedded) {
    m_surfaceTriangles = geometry.surface->triangles;
    m_surfaceRest_m = geometry.surface->vertices_m;
  } else {
    m_surfaceTriangles = boundaryFaces(geometry.mesh);
    m_surfaceRest_m = springs.restPositions_m;
  }
  m_surface->SetPoints(makePoints(m_surfaceRest_m.cols()));
  vtkNew<vtkCellArray> triangles;
  for (Eigen::Index t = 0; t < m_surfaceTriangles.cols(); ++t) {
    const vtkIdType corners[3] = {m_surfaceTriangles(0, t), m_surfaceTriangles(1, t),
                                  m_surfaceTriangles(2, t)};
    triangles->InsertNextCell(3, corners);
  }
  m_surface->SetPolys(triangles);
  addFrameArrays(m_surface, m_surfaceRest_m.cols());

  buildTetGrid();
}

void TimeSeriesExport::buildTetGrid() {
  m_tets = vtkSmartPointer<vtkUnstructuredGrid>::New();
  const TetMesh& mesh = m_geometry.mesh;
  m_tets->SetPoints(makePoints(m_springs.nodeCount()));
  m_tets->Allocate(mesh.tets.cols());
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    const vtkIdType corners[4] = {mesh.tets(0, t), mesh.tets(1, t), mesh.tets(2, t),
                                  mesh.tets(3, t)};
    m_tets->InsertNextCell(VTK_TETRA, 4, corners);
  }
  addFrameArrays(m_tets, m_springs.nodeCount());
}

TimeSeriesExport::~TimeSeriesExport() = default;

void TimeSeriesExport::write(double time_s, const Eigen::Matrix3Xd& x) {
  const std::size_t frame = m_times.size();
  // The body made again where the tool aims (Simulation::refineTowardsTool): its new tets.
  if (m_tets->GetNumberOfPoints() != m_springs.nodeCount()) buildTetGrid();
  nodeStretch(m_springs, x, m_nodeStretch);
  setFrame(m_tets, x, m_springs.restPositions_m, m_nodeStretch);
  if (m_geometry.surface && m_geometry.embedding) {
    m_surfaceX.resize(3, m_surfaceRest_m.cols());
    m_geometry.embedding->apply(x, m_surfaceX);
    m_geometry.embedding->interpolate(m_nodeStretch, m_surfaceStretch);
    setFrame(m_surface, m_surfaceX, m_surfaceRest_m, m_surfaceStretch);
  } else {
    setFrame(m_surface, x, m_surfaceRest_m, m_nodeStretch);
  }
  vtkNew<vtkXMLPolyDataWriter> surfaceWriter;
  surfaceWriter->SetInputData(m_surface);
  writeAtomically(surfaceWriter.Get(), m_folder / frameName("surface", frame, "vtp"));
  vtkNew<vtkXMLUnstructuredGridWriter> tetWriter;
  tetWriter->SetInputData(m_tets);
  writeAtomically(tetWriter.Get(), m_folder / frameName("tets", frame, "vtu"));
  m_times.push_back(time_s);
  writeCollection();
}

void TimeSeriesExport::writeCollection() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  out.precision(9);
  for (std::size_t frame = 0; frame < m_times.size(); ++frame) {
    out << "    <DataSet timestep=\"" << m_times[frame] << "\" part=\"0\" file=\""
        << frameName("surface", frame, "vtp") << "\"/>\n"
        << "    <DataSet timestep=\"" << m_times[frame] << "\" part=\"1\" file=\""
        << frameName("tets", frame, "vtu") << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  writeWholeFile(m_collection, out.str());
}

}  // namespace tissuesim
