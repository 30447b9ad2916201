// SPDX-License-Identifier: Apache-2.0
#pragma once
// VTK's own mesh files, common in this field: legacy .vtk (polydata or unstructured grid),
// XML .vtp (surfaces) and .vtu (volumes). Read here because they need VTK, which core must not
// see; the results are core's plain types. VTK's readers run in a child process
// (mesh/IsolatedMeshRead.h), as assimp's do: a malformed file cannot crash or hang the program.

#include <filesystem>

#include "mesh/TetMeshFile.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

bool isVtkMeshFile(const std::filesystem::path& path);

/// Triangles of a .vtk polydata or .vtp file (polygons with more sides are fanned).
/// @throws MeshFileError naming the file.
TriangleSurface readVtkSurface(const std::filesystem::path& path, double metresPerUnit = 1.0);

/// Tets of a .vtk unstructured grid or .vtu file; other cells are skipped and counted in the
/// report. Orientation is checked as for every tet mesh (checkTetOrientation).
/// @throws MeshFileError naming the file.
TetMesh readVtkTetMesh(const std::filesystem::path& path, double metresPerUnit = 1.0,
                       TetMeshReadReport* report = nullptr);

}  // namespace tissuesim
