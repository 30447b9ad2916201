// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading organ surfaces through assimp: STL, OBJ, PLY, OFF and glTF/GLB, the formats an organ's
// surface comes in; others are refused by their extension before assimp sees them. assimp runs
// in a child process under memory and time limits (IsolatedCall.h): a file that crashes or
// hangs it is refused with one line, and the program, and the window's running scene, go on.
// Node transforms are applied; each assimp mesh is a named part.

#include <filesystem>
#include <string>
#include <vector>

#include "mesh/TriangleSurface.h"

namespace tissuesim {

struct SurfaceReadOptions {
  double metresPerUnit = 1.0;  ///< e.g. 0.01 for a file in centimetres; any scale the scene gives
  std::string part;            ///< one part by name; empty: all parts merged
};

/// Files larger than this are refused before reading (a liver surface is a few MB).
constexpr std::uintmax_t kMaxMeshFileBytes = 256ull << 20;

/// The parts (named meshes) in a file, in order.
std::vector<std::string> listSurfaceParts(const std::filesystem::path& path);

/// Reads, scales and merges (or selects) the parts. Vertices are not welded here. The same file
/// read again unchanged (its size and modification time), with the same options, comes from the
/// process's last eight reads rather than a new child process (SurfaceReader.cpp says why).
/// @throws MeshFileError naming the file: unreadable, unknown format, no triangles, unknown
/// part, non-finite or absurd coordinates (beyond 100 m after scaling: check the units).
TriangleSurface readSurface(const std::filesystem::path& path, const SurfaceReadOptions& options);

}  // namespace tissuesim
