// SPDX-License-Identifier: Apache-2.0
#pragma once
// A mesh reader run in a child process (IsolatedCall.h): the library that parses a file from
// anywhere (assimp, VTK) cannot crash or hang the program. The child sends the mesh back as
// bytes (two counts, then the arrays); a crash, a limit reached or a hang in the child, or a
// reply that does not add up, becomes a MeshFileError naming the file. The child's limits are
// IsolationLimits' (60 s), or TISSUESIM_READER_SECONDS seconds of wall and CPU time when that
// is set (the fuzz runs set 2, so that a file that hangs the library costs two seconds there).

#include <filesystem>
#include <functional>
#include <string>

#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {

/// Runs work() in a child; its bytes, or a MeshFileError (work()'s own message when it threw).
std::string runReaderIsolated(const std::filesystem::path& path,
                              const std::function<std::string()>& work);

/// read() in a child, its surface sent back. @throws MeshFileError.
TriangleSurface readSurfaceIsolated(const std::filesystem::path& path,
                                    const std::function<TriangleSurface()>& read);

/// A tet mesh as a reader returns it: the mesh and the elements it skipped.
struct ReadTetMesh {
  TetMesh mesh;
  int skippedElements = 0;
};

/// read() in a child, its mesh and skipped count sent back. @throws MeshFileError.
ReadTetMesh readTetMeshIsolated(const std::filesystem::path& path,
                                const std::function<ReadTetMesh()>& read);

}  // namespace tissuesim
