// SPDX-License-Identifier: Apache-2.0
#include "mesh/IsolatedMeshRead.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "mesh/IsolatedCall.h"

namespace tissuesim {

namespace {

template <typename T>
void append(std::string& bytes, const T* data, std::size_t count) {
  bytes.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

/// Two counts, then a 3 x first array of Scalar and a K x second array of int.
template <typename Scalar, int K>
std::string pack(const Eigen::Matrix<Scalar, 3, Eigen::Dynamic>& points,
                 const Eigen::Matrix<int, K, Eigen::Dynamic>& cells, std::int64_t extra) {
  const std::array<std::int64_t, 3> header{points.cols(), cells.cols(), extra};
  std::string bytes;
  append(bytes, header.data(), header.size());
  append(bytes, points.data(), static_cast<std::size_t>(points.size()));
  append(bytes, cells.data(), static_cast<std::size_t>(cells.size()));
  return bytes;
}

/// The inverse of pack(), checking that the counts and the length agree before any copy.
template <typename Scalar, int K>
std::int64_t unpack(const std::string& bytes, const std::filesystem::path& path,
                    Eigen::Matrix<Scalar, 3, Eigen::Dynamic>& points,
                    Eigen::Matrix<int, K, Eigen::Dynamic>& cells) {
  std::array<std::int64_t, 3> header{};
  const auto incomplete = [&] {
    return MeshFileError(path.string() + ": the reader process sent back an incomplete mesh");
  };
  if (bytes.size() < sizeof header) throw incomplete();
  std::memcpy(header.data(), bytes.data(), sizeof header);
  // Counts bounded by what the bytes can hold, so no count sizes an allocation by itself.
  const auto limit = static_cast<std::int64_t>(bytes.size());
  if (header[0] < 0 || header[1] < 0 || header[0] > limit || header[1] > limit) throw incomplete();
  const std::size_t pointBytes = static_cast<std::size_t>(3 * header[0]) * sizeof(Scalar);
  const std::size_t cellBytes = static_cast<std::size_t>(K * header[1]) * sizeof(int);
  if (bytes.size() != sizeof header + pointBytes + cellBytes) throw incomplete();
  points.resize(3, header[0]);
  cells.resize(K, header[1]);
  std::memcpy(points.data(), bytes.data() + sizeof header, pointBytes);
  std::memcpy(cells.data(), bytes.data() + sizeof header + pointBytes, cellBytes);
  return header[2];
}

/// Every index names a point: the reply comes from a library the parent does not trust.
template <int K>
void checkIndices(const Eigen::Matrix<int, K, Eigen::Dynamic>& cells, Eigen::Index pointCount,
                  const std::filesystem::path& path) {
  if (cells.size() == 0) return;
  if (cells.minCoeff() < 0 || cells.maxCoeff() >= pointCount) {
    throw MeshFileError(path.string() +
                        ": the reader sent back an element naming a point the "
                        "mesh does not have");
  }
}

}  // namespace

std::string runReaderIsolated(const std::filesystem::path& path,
                              const std::function<std::string()>& work) {
  IsolationLimits limits;
  if (const char* seconds = std::getenv("TISSUESIM_READER_SECONDS")) {
    const int value = std::atoi(seconds);
    if (value > 0) {
      limits.wallTime = std::chrono::seconds(value);
      limits.cpuSeconds = value;
    }
  }
  const IsolatedResult result = runIsolated(work, limits);
  if (result.isOk) return result.bytes;
  if (result.isThrown) throw MeshFileError(result.error);  // names the file already
  throw MeshFileError(path.string() + ": " + result.error);
}

TriangleSurface readSurfaceIsolated(const std::filesystem::path& path,
                                    const std::function<TriangleSurface()>& read) {
  const std::string bytes = runReaderIsolated(path, [&] {
    const TriangleSurface surface = read();
    return pack(surface.vertices_m, surface.triangles, 0);
  });
  TriangleSurface surface;
  unpack(bytes, path, surface.vertices_m, surface.triangles);
  checkIndices(surface.triangles, surface.vertexCount(), path);
  return surface;
}

ReadTetMesh readTetMeshIsolated(const std::filesystem::path& path,
                                const std::function<ReadTetMesh()>& read) {
  const std::string bytes = runReaderIsolated(path, [&] {
    const ReadTetMesh result = read();
    return pack(result.mesh.nodes_m, result.mesh.tets, result.skippedElements);
  });
  ReadTetMesh result;
  result.skippedElements =
      static_cast<int>(unpack(bytes, path, result.mesh.nodes_m, result.mesh.tets));
  checkIndices(result.mesh.tets, result.mesh.nodeCount(), path);
  return result;
}

}  // namespace tissuesim
