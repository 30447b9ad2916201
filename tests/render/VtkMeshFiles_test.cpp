// SPDX-License-Identifier: Apache-2.0
#include "render/VtkMeshFiles.h"

#include <csignal>

#include "mesh/IsolatedMeshRead.h"

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

std::string meshPath(const std::string& name) {
  return std::string(TISSUESIM_TEST_DATA_DIR) + "/meshes/" + name;
}

TEST(VtkMeshFiles, ReadsAnUnstructuredGridKeepingTets) {
  TetMeshReadReport report;
  const TetMesh mesh = readVtkTetMesh(meshPath("two-tets.vtk"), 0.01, &report);
  EXPECT_EQ(mesh.tetCount(), 2);
  EXPECT_EQ(report.skippedElements, 1);
  EXPECT_NEAR(inspectTets(mesh).totalVolume_m3, 0.5e-6, 1e-15);
}

TEST(VtkMeshFiles, ReadsAPolydataSurface) {
  const TriangleSurface cube = readVtkSurface(meshPath("cube-polydata.vtk"));
  EXPECT_EQ(cube.triangleCount(), 12);
  EXPECT_NEAR(enclosedVolume(cube), 1.0, 1e-12);
}

TEST(VtkMeshFiles, ReadsTheXmlFormats) {
  TetMeshReadReport report;
  const TetMesh mesh = readVtkTetMesh(meshPath("two-tets.vtu"), 1.0, &report);
  EXPECT_EQ(mesh.tetCount(), 2);
  EXPECT_EQ(report.skippedElements, 1);
  EXPECT_NEAR(inspectTets(mesh).totalVolume_m3, 0.5, 1e-12);
  const TriangleSurface cube = readVtkSurface(meshPath("cube.vtp"));
  EXPECT_EQ(cube.triangleCount(), 12);
  EXPECT_NEAR(enclosedVolume(cube), 1.0, 1e-12);
}

TEST(VtkMeshFiles, RefusesWithOneLine) {
  for (const auto& [file, expected] :
       {std::pair{"cube.obj", "not a legacy VTK file"}, std::pair{"missing.vtu", "cannot open"},
        std::pair{"cube-polydata.vtk", "no tetrahedra"},
        std::pair{"cube.vtp", "no tetrahedra (6 other cells)"}}) {
    try {
      readVtkTetMesh(meshPath(file));
      ADD_FAILURE() << file << " accepted";
    } catch (const MeshFileError& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  }
}

TEST(VtkMeshFiles, ACellNamingAPointThatIsNotThereIsRefused) {
  // VTK passes such ids through; found by fuzzing (tests/fuzz/crashers/vtk_mesh).
  try {
    readVtkSurface(meshPath("point-out-of-range.vtk"));
    ADD_FAILURE() << "accepted";
  } catch (const MeshFileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("point-out-of-range.vtk: cell 5 refers to point 99, but the file has 8 "
                        "points"),
              std::string::npos)
        << error.what();
  }
}

TEST(VtkMeshFiles, AReaderThatCrashesIsAnErrorNotACrash) {
  // The VTK readers run in a child process: a file that crashes them costs one line. A child
  // that dies is simulated by a read that kills itself.
  try {
    readSurfaceIsolated("x.vtk", []() -> TriangleSurface {
      std::raise(SIGSEGV);
      return {};
    });
    ADD_FAILURE() << "a crashed reader returned";
  } catch (const MeshFileError& error) {
    EXPECT_NE(std::string(error.what()).find("x.vtk: the importer crashed on it"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace tissuesim
