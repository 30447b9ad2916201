// SPDX-License-Identifier: Apache-2.0
// The ParaView export: what is written reads back as the state that was written.
#include "render/TimeSeriesExport.h"

#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "render/VtkMeshFiles.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"
#include "springs/NodeStretch.h"

namespace tissuesim {
namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(folder);
  return folder;
}

TEST(TimeSeriesExport, FramesReadBackAsTheStatesWritten) {
  const Simulation simulation(
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
  const SpringMesh& springs = simulation.springMesh();
  const std::filesystem::path folder = freshFolder("tissuesim-export-test");
  TimeSeriesExport exporter(folder, simulation.geometry(), springs);
  // Two frames: the unloaded mesh and the liver settled on its tray.
  exporter.write(0.0, springs.restPositions_m);
  const Eigen::Matrix3Xd& settled = simulation.state().x;
  exporter.write(0.25, settled);
  EXPECT_EQ(exporter.frameCount(), 2);

  // The tet mesh: positions, displacement from the unloaded mesh, and the colour map's stretch.
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((folder / "tets_000001.vtu").c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), springs.nodeCount());
  EXPECT_EQ(grid->GetNumberOfCells(), simulation.geometry().mesh.tetCount());
  auto* displacement = vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("displacement"));
  auto* stretch = vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("stretch"));
  ASSERT_NE(displacement, nullptr);
  ASSERT_NE(stretch, nullptr);
  Eigen::VectorXd expectedStretch;
  nodeStretch(springs, settled, expectedStretch);
  double largestDisplacement_m = 0.0;
  for (Eigen::Index i = 0; i < springs.nodeCount(); ++i) {
    double point[3], d[3];
    grid->GetPoint(i, point);
    displacement->GetTuple(i, d);
    for (int c = 0; c < 3; ++c) {
      EXPECT_DOUBLE_EQ(point[c], settled(c, i));
      EXPECT_DOUBLE_EQ(d[c], settled(c, i) - springs.restPositions_m(c, i));
    }
    EXPECT_DOUBLE_EQ(stretch->GetValue(i), expectedStretch[i]);
    largestDisplacement_m = std::max(largestDisplacement_m, Eigen::Vector3d(d).norm());
  }
  EXPECT_GT(largestDisplacement_m, 0.005);  // it sagged, and the file says so

  // The drawn surface: the embedded positions, as the window draws them.
  const TriangleSurface surface = readVtkSurface(folder / "surface_000001.vtp");
  Eigen::Matrix3Xd drawn(3, simulation.geometry().surface->vertexCount());
  simulation.geometry().embedding->apply(settled, drawn);
  ASSERT_EQ(surface.vertexCount(), drawn.cols());
  EXPECT_EQ(surface.triangles, simulation.geometry().surface->triangles);
  EXPECT_LT((surface.vertices_m - drawn).cwiseAbs().maxCoeff(), 1e-15);

  // The collection lists both frames, each with its time, and no partial file is left.
  std::ifstream collection(folder / "series.pvd");
  std::stringstream text;
  text << collection.rdbuf();
  EXPECT_NE(text.str().find("timestep=\"0.25\" part=\"1\" file=\"tets_000001.vtu\""),
            std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("timestep=\"0\" part=\"0\" file=\"surface_000000.vtp\""),
            std::string::npos);
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    EXPECT_NE(entry.path().extension(), ".partial") << entry.path();
  std::filesystem::remove_all(folder);
}

TEST(TimeSeriesExport, AFolderThatCannotBeMadeIsNamed) {
  const Simulation simulation(
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
  try {
    TimeSeriesExport exporter("/proc/no-such-folder", simulation.geometry(),
                              simulation.springMesh());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(
        std::string(error.what()).find("cannot create the export folder /proc/no-such-folder"),
        std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace tissuesim
