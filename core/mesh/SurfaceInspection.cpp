// SPDX-License-Identifier: Apache-2.0
#include "mesh/SurfaceInspection.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

namespace tissuesim {
namespace {

using Edge = std::pair<int, int>;

/// Directed edges of every triangle, counted undirected.
std::map<Edge, int> countEdges(const TriangleSurface& surface) {
  std::map<Edge, int> counts;
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = surface.triangles(k, f);
      const int b = surface.triangles((k + 1) % 3, f);
      ++counts[{std::min(a, b), std::max(a, b)}];
    }
  }
  return counts;
}

std::vector<SurfaceHole> findHoles(const TriangleSurface& surface,
                                   const std::map<Edge, int>& counts) {
  // Boundary edges keep their triangle's direction, so loops can be walked a -> b.
  std::multimap<int, int> next;
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = surface.triangles(k, f);
      const int b = surface.triangles((k + 1) % 3, f);
      if (counts.at({std::min(a, b), std::max(a, b)}) == 1)
        next.emplace(b, a);  // reversed: hole orientation
    }
  }
  std::vector<SurfaceHole> holes;
  while (!next.empty()) {
    SurfaceHole hole;
    const int start = next.begin()->first;
    int current = start;
    while (true) {
      const auto it = next.find(current);
      if (it == next.end()) break;
      hole.loop.push_back(current);
      const int following = it->second;
      next.erase(it);
      current = following;
      if (current == start) break;
    }
    for (std::size_t i = 0; i < hole.loop.size(); ++i) {
      const Eigen::Vector3d p = surface.vertices_m.col(hole.loop[i]);
      hole.perimeter_m +=
          (surface.vertices_m.col(hole.loop[(i + 1) % hole.loop.size()]) - p).norm();
      for (std::size_t j = i + 1; j < hole.loop.size(); ++j) {
        hole.diameter_m =
            std::max(hole.diameter_m, (surface.vertices_m.col(hole.loop[j]) - p).norm());
      }
    }
    holes.push_back(std::move(hole));
  }
  return holes;
}

}  // namespace

std::string SurfaceReport::summary() const {
  std::ostringstream out;
  out << vertices << " vertices, " << triangles << " triangles, " << openEdges << " open edges in "
      << holes.size() << " holes, " << nonManifoldEdges << " non-manifold edges, "
      << degenerateTriangles << " degenerate triangles, " << unusedVertices << " unused vertices";
  return out.str();
}

int weldVertices(TriangleSurface& surface, double tolerance_m) {
  const Eigen::Index count = surface.vertexCount();
  std::vector<int> representative(static_cast<std::size_t>(count));
  // Hash by cell of size tolerance; compare with the 27 neighbouring cells.
  const double cell = std::max(tolerance_m, 1e-15);
  struct Key {
    long long x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
  };
  std::unordered_map<Key, std::vector<int>, Hash> grid;
  int merged = 0;
  for (Eigen::Index v = 0; v < count; ++v) {
    const Eigen::Vector3d p = surface.vertices_m.col(v);
    const Key key{std::llround(std::floor(p.x() / cell)), std::llround(std::floor(p.y() / cell)),
                  std::llround(std::floor(p.z() / cell))};
    int found = -1;
    for (long long dx = -1; dx <= 1 && found < 0; ++dx) {
      for (long long dy = -1; dy <= 1 && found < 0; ++dy) {
        for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({key.x + dx, key.y + dy, key.z + dz});
          if (it == grid.end()) continue;
          for (const int other : it->second) {
            if ((surface.vertices_m.col(other) - p).norm() <= tolerance_m) {
              found = other;
              break;
            }
          }
        }
      }
    }
    if (found >= 0) {
      representative[static_cast<std::size_t>(v)] = found;
      ++merged;
    } else {
      representative[static_cast<std::size_t>(v)] = static_cast<int>(v);
      grid[key].push_back(static_cast<int>(v));
    }
  }
  // Remap triangles, drop the collapsed ones, then compact the vertices.
  std::vector<Eigen::Vector3i> kept;
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k)
      t[k] = representative[static_cast<std::size_t>(surface.triangles(k, f))];
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) kept.push_back(t);
  }
  std::vector<int> newIndex(static_cast<std::size_t>(count), -1);
  int used = 0;
  for (const Eigen::Vector3i& t : kept) {
    for (int k = 0; k < 3; ++k) {
      if (newIndex[static_cast<std::size_t>(t[k])] < 0)
        newIndex[static_cast<std::size_t>(t[k])] = used++;
    }
  }
  Eigen::Matrix3Xd vertices(3, used);
  for (Eigen::Index v = 0; v < count; ++v) {
    if (newIndex[static_cast<std::size_t>(v)] >= 0)
      vertices.col(newIndex[static_cast<std::size_t>(v)]) = surface.vertices_m.col(v);
  }
  surface.vertices_m = std::move(vertices);
  surface.triangles.resize(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t f = 0; f < kept.size(); ++f) {
    for (int k = 0; k < 3; ++k)
      surface.triangles(k, static_cast<Eigen::Index>(f)) =
          newIndex[static_cast<std::size_t>(kept[f][k])];
  }
  return merged;
}

SurfaceReport inspectSurface(const TriangleSurface& surface) {
  SurfaceReport report;
  report.vertices = surface.vertexCount();
  report.triangles = surface.triangleCount();
  if (report.vertices > 0) {
    report.boundingDiagonal_m =
        (surface.vertices_m.rowwise().maxCoeff() - surface.vertices_m.rowwise().minCoeff()).norm();
  }
  const std::map<Edge, int> counts = countEdges(surface);
  for (const auto& [edge, count] : counts) {
    report.openEdges += count == 1 ? 1 : 0;
    report.nonManifoldEdges += count >= 3 ? 1 : 0;
  }
  const double minArea = std::pow(1e-6 * report.boundingDiagonal_m, 2);
  std::vector<char> isUsed(static_cast<std::size_t>(report.vertices), 0);
  for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
    const Eigen::Vector3d a = surface.vertices_m.col(surface.triangles(0, f));
    const Eigen::Vector3d b = surface.vertices_m.col(surface.triangles(1, f));
    const Eigen::Vector3d c = surface.vertices_m.col(surface.triangles(2, f));
    report.degenerateTriangles += 0.5 * (b - a).cross(c - a).norm() <= minArea ? 1 : 0;
    for (int k = 0; k < 3; ++k) isUsed[static_cast<std::size_t>(surface.triangles(k, f))] = 1;
  }
  report.unusedVertices = static_cast<int>(std::count(isUsed.begin(), isUsed.end(), 0));
  if (report.nonManifoldEdges == 0) report.holes = findHoles(surface, counts);
  report.enclosedVolume_m3 = enclosedVolume(surface);
  return report;
}

int closeSmallHoles(TriangleSurface& surface, double maxDiameter_m) {
  const SurfaceReport report = inspectSurface(surface);
  int closed = 0;
  for (const SurfaceHole& hole : report.holes) {
    if (hole.diameter_m > maxDiameter_m || hole.loop.size() < 3) continue;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const int v : hole.loop) centroid += surface.vertices_m.col(v);
    centroid /= static_cast<double>(hole.loop.size());
    const Eigen::Index centre = surface.vertexCount();
    surface.vertices_m.conservativeResize(3, centre + 1);
    surface.vertices_m.col(centre) = centroid;
    const Eigen::Index first = surface.triangleCount();
    surface.triangles.conservativeResize(3, first + static_cast<Eigen::Index>(hole.loop.size()));
    for (std::size_t i = 0; i < hole.loop.size(); ++i) {
      surface.triangles.col(first + static_cast<Eigen::Index>(i)) << hole.loop[i],
          hole.loop[(i + 1) % hole.loop.size()], static_cast<int>(centre);
    }
    ++closed;
  }
  return closed;
}

}  // namespace tissuesim
