// SPDX-License-Identifier: Apache-2.0
#include "mesh/SurfaceReader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <deque>
#include <functional>
#include <mutex>
#include <system_error>
#include <tuple>
#include <utility>

#include "mesh/IsolatedMeshRead.h"

namespace tissuesim {
namespace {

/// The formats an organ's surface comes in: medical and CAD exports (STL, OBJ, PLY, OFF) and
/// glTF. assimp reads dozens more (game and scene formats), the least tested of its readers;
/// they are refused before assimp sees them.
constexpr std::array<const char*, 6> kSurfaceExtensions = {".stl", ".obj",  ".ply",
                                                           ".off", ".gltf", ".glb"};

/// Beyond this the units are almost certainly wrong (an organ is centimetres to decimetres).
constexpr double kMaxCoordinate_m = 100.0;

/// assimp on a file checkSurfaceFile() has passed (in the child process).
const aiScene* importScene(Assimp::Importer& importer, const std::filesystem::path& path) {
  const std::string name = path.string();
  // No vertex joining here: welding is ours (SurfaceInspection), with a stated tolerance.
  // assimp fails on paths with '..' when an OBJ names a material file: give it a normal one.
  const std::string normal = std::filesystem::absolute(path).lexically_normal().string();
  const aiScene* scene = importer.ReadFile(normal, aiProcess_Triangulate | aiProcess_SortByPType);
  if (scene == nullptr) {
    throw MeshFileError(name + ": not a readable surface (" + importer.GetErrorString() + ")");
  }
  if (scene->mNumMeshes == 0) throw MeshFileError(name + ": the file holds no mesh");
  return scene;
}

std::string partName(const aiScene* scene, unsigned mesh) {
  const std::string name = scene->mMeshes[mesh]->mName.C_Str();
  return name.empty() ? "part" + std::to_string(mesh) : name;
}

std::vector<std::string> importPartNames(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importScene(importer, path);
  std::vector<std::string> names;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) names.push_back(partName(scene, m));
  return names;
}

TriangleSurface importSurface(const std::filesystem::path& path,
                              const SurfaceReadOptions& options) {
  const std::string name = path.string();
  Assimp::Importer importer;
  const aiScene* scene = importScene(importer, path);
  if (!options.part.empty()) {
    bool isFound = false;
    std::string names;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      isFound = isFound || partName(scene, m) == options.part;
      names += (m == 0 ? "" : ", ") + partName(scene, m);
    }
    if (!isFound) throw MeshFileError(name + ": no part '" + options.part + "'; parts: " + names);
  }

  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  // Walk the node tree so each mesh gets its node's transform.
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    const aiMatrix4x4 transform = parent * node->mTransformation;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const unsigned m = node->mMeshes[k];
      if (m >= scene->mNumMeshes) {
        throw MeshFileError(name + ": a node names mesh " + std::to_string(m) + " of " +
                            std::to_string(scene->mNumMeshes));
      }
      if (!options.part.empty() && partName(scene, m) != options.part) continue;
      const aiMesh* mesh = scene->mMeshes[m];
      const int offset = static_cast<int>(vertices.size());
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = transform * mesh->mVertices[v];
        vertices.emplace_back(p.x * options.metresPerUnit, p.y * options.metresPerUnit,
                              p.z * options.metresPerUnit);
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines are not surface
        // The importers pass some files' indices through unchecked (a PLY face naming vertex 7
        // of 4, found by fuzzing).
        for (unsigned c = 0; c < 3; ++c) {
          if (face.mIndices[c] >= mesh->mNumVertices) {
            throw MeshFileError(name + ": face " + std::to_string(f) + " refers to vertex " +
                                std::to_string(face.mIndices[c]) + ", but its mesh has " +
                                std::to_string(mesh->mNumVertices) + " vertices");
          }
        }
        triangles.emplace_back(offset + static_cast<int>(face.mIndices[0]),
                               offset + static_cast<int>(face.mIndices[1]),
                               offset + static_cast<int>(face.mIndices[2]));
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], transform);
  };
  visit(scene->mRootNode, aiMatrix4x4());
  if (triangles.empty()) throw MeshFileError(name + ": the file holds no triangles");

  TriangleSurface surface;
  surface.vertices_m.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Eigen::Vector3d& p = vertices[v];
    if (!p.allFinite()) {
      throw MeshFileError(name + ": vertex " + std::to_string(v) +
                          " has a coordinate that is not finite");
    }
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinate_m) {
      throw MeshFileError(name + ": vertex " + std::to_string(v) + " lies " +
                          std::to_string(p.cwiseAbs().maxCoeff()) +
                          " m from the origin after scaling; expected an organ within 100 m "
                          "(check the units or the scale)");
    }
    surface.vertices_m.col(static_cast<Eigen::Index>(v)) = p;
  }
  surface.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    surface.triangles.col(static_cast<Eigen::Index>(f)) = triangles[f];
  }
  return surface;
}

/// The file checks a person should get before any import: there, a file, not empty, not huge,
/// and of a format an organ comes in.
void checkSurfaceFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw MeshFileError(name + ": cannot open the surface file (missing or not a file)");
  }
  const auto size = std::filesystem::file_size(path, error);
  if (!error && size == 0) throw MeshFileError(name + ": the file is empty");
  if (!error && size > kMaxMeshFileBytes) {
    throw MeshFileError(name + ": " + std::to_string(size >> 20) +
                        " MiB is beyond the limit of 256 MiB for a mesh file");
  }
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (std::find(kSurfaceExtensions.begin(), kSurfaceExtensions.end(), extension) ==
      kSurfaceExtensions.end()) {
    std::string list;
    for (const char* each : kSurfaceExtensions)
      list += (list.empty() ? "" : ", ") + std::string(each);
    throw MeshFileError(name + ": '" + extension +
                        "' is not a surface format read here; expected one of " + list);
  }
}

}  // namespace

std::vector<std::string> listSurfaceParts(const std::filesystem::path& path) {
  checkSurfaceFile(path);
  const std::string bytes = runReaderIsolated(path, [&] {
    std::string joined;
    for (const std::string& part : importPartNames(path)) joined += part + '\n';
    return joined;
  });
  std::vector<std::string> names;
  std::size_t start = 0;
  for (std::size_t end = bytes.find('\n'); end != std::string::npos;
       start = end + 1, end = bytes.find('\n', start)) {
    names.push_back(bytes.substr(start, end - start));
  }
  return names;
}

namespace {

/// A surface read, by the file as it was then (its canonical path, size and modification time)
/// and the options it was read with.
struct SurfaceReadKey {
  std::string path;
  std::uintmax_t bytes = 0;
  std::filesystem::file_time_type::rep modified = 0;
  double metresPerUnit = 1.0;
  std::string part;

  bool operator==(const SurfaceReadKey& other) const {
    return std::tie(path, bytes, modified, metresPerUnit, part) ==
           std::tie(other.path, other.bytes, other.modified, other.metresPerUnit, other.part);
  }
};

/// The last surfaces this process read. A scene opened again (a second simulation of it, the
/// window's next scene on the same organ) takes its surface from here instead of parsing the file
/// again in a child process: a fork while other threads run (a body's updates, a thread pool) is
/// safe with glibc's allocator, not with every one (AddressSanitizer's keeps its locks across
/// it, and a child forked while another thread held one never finishes).
class ReadSurfaces {
 public:
  static constexpr std::size_t kKept = 8;

  bool find(const SurfaceReadKey& key, TriangleSurface& surface) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    for (const auto& [kept, keptSurface] : m_read) {
      if (kept == key) {
        surface = keptSurface;
        return true;
      }
    }
    return false;
  }
  void keep(SurfaceReadKey key, const TriangleSurface& surface) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    if (m_read.size() == kKept) m_read.pop_front();
    m_read.emplace_back(std::move(key), surface);
  }

 private:
  std::mutex m_mutex;
  std::deque<std::pair<SurfaceReadKey, TriangleSurface>> m_read;
};

ReadSurfaces& readSurfaces() {
  static ReadSurfaces instance;
  return instance;
}

}  // namespace

TriangleSurface readSurface(const std::filesystem::path& path, const SurfaceReadOptions& options) {
  const std::string name = path.string();
  if (!(options.metresPerUnit > 0.0) || !std::isfinite(options.metresPerUnit)) {
    throw MeshFileError(name + ": the scale must be a positive number of metres per unit");
  }
  checkSurfaceFile(path);
  std::array<std::error_code, 3> errors;
  SurfaceReadKey key;
  key.path = std::filesystem::canonical(path, errors[0]).string();
  key.bytes = std::filesystem::file_size(path, errors[1]);
  key.modified = std::filesystem::last_write_time(path, errors[2]).time_since_epoch().count();
  key.metresPerUnit = options.metresPerUnit;
  key.part = options.part;
  const bool isKnowable = !errors[0] && !errors[1] && !errors[2];
  TriangleSurface surface;
  if (isKnowable && readSurfaces().find(key, surface)) return surface;
  surface = readSurfaceIsolated(path, [&] { return importSurface(path, options); });
  if (isKnowable) readSurfaces().keep(std::move(key), surface);
  return surface;
}

}  // namespace tissuesim
