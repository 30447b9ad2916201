// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading and writing tetrahedral meshes:
//   Gmsh .msh ASCII, format 1 ($NOD/$ELM, as SOFA's liver), 2.2 and 4.1 (read); 2.2 (write)
//   TetGen .node + .ele (read; either file may be named)
// Only tets are kept; other elements (triangles, lines, points) are skipped and counted.
// VTK's .vtk/.vtu grids are read in render/ (they need VTK, which core must not see).
//
// Orientation: if every tet is negatively oriented the file uses the opposite convention and
// all are re-oriented (noted); if only some are, the mesh is folded and is refused, as are
// zero-volume tets, indices out of range, non-finite coordinates and meshes with no tets.

#include <filesystem>
#include <string>

#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

struct TetMeshReadReport {
  int skippedElements = 0;     ///< non-tet elements ignored
  bool wasReoriented = false;  ///< every tet was flipped to positive orientation
  std::string format;          ///< "gmsh 1", "gmsh 2.2", "gmsh 4.1", "tetgen"
};

/// @throws MeshFileError naming the file and line.
TetMesh readTetMesh(const std::filesystem::path& path, double metresPerUnit = 1.0,
                    TetMeshReadReport* report = nullptr);

/// Checks orientation and degeneracy as above (used by every reader). @throws MeshFileError.
void checkTetOrientation(TetMesh& mesh, const std::string& name, TetMeshReadReport* report);

/// Gmsh 2.2 ASCII, coordinates in metres. @throws MeshFileError if it cannot write.
void writeGmsh(const std::filesystem::path& path, const TetMesh& mesh);

/// True for the extensions readTetMesh handles (.msh, .node, .ele).
bool isTetMeshFile(const std::filesystem::path& path);

}  // namespace tissuesim
