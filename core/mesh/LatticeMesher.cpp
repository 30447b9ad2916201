// SPDX-License-Identifier: Apache-2.0
#include "mesh/LatticeMesher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "mesh/BlockMesher.h"

namespace tissuesim {
namespace {

/// For each cell centre, how many of the three ray directions find it inside.
std::vector<int> insideVotes(const TriangleSurface& surface, const Eigen::Vector3d& origin,
                             double h, const Eigen::Vector3i& cells) {
  std::vector<int> votes(static_cast<std::size_t>(cells.prod()), 0);
  const auto cellIndex = [&](const Eigen::Vector3i& c) {
    return static_cast<std::size_t>(c.x() + cells.x() * (c.y() + cells.y() * c.z()));
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    // Hits along each row of centres parallel to `axis`, row (j, k) at u = (j + 1/2) h.
    std::vector<std::vector<double>> hits(static_cast<std::size_t>(cells[u] * cells[v]));
    for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
      const Eigen::Vector3d a = surface.vertices_m.col(surface.triangles(0, f)) - origin;
      const Eigen::Vector3d b = surface.vertices_m.col(surface.triangles(1, f)) - origin;
      const Eigen::Vector3d c = surface.vertices_m.col(surface.triangles(2, f)) - origin;
      const double uMin = std::min({a[u], b[u], c[u]}), uMax = std::max({a[u], b[u], c[u]});
      const double vMin = std::min({a[v], b[v], c[v]}), vMax = std::max({a[v], b[v], c[v]});
      const int j0 = std::max(0, static_cast<int>(std::ceil(uMin / h - 0.5)));
      const int j1 = std::min(cells[u] - 1, static_cast<int>(std::floor(uMax / h - 0.5)));
      const int k0 = std::max(0, static_cast<int>(std::ceil(vMin / h - 0.5)));
      const int k1 = std::min(cells[v] - 1, static_cast<int>(std::floor(vMax / h - 0.5)));
      const double det = (b[u] - a[u]) * (c[v] - a[v]) - (c[u] - a[u]) * (b[v] - a[v]);
      if (det == 0.0) continue;  // edge-on to this direction
      for (int j = j0; j <= j1; ++j) {
        for (int k = k0; k <= k1; ++k) {
          // A tiny irrational offset keeps rays off edges and vertices shared by triangles.
          const double pu = (j + 0.5) * h + 1.234567e-9 * h;
          const double pv = (k + 0.5) * h + 2.345678e-9 * h;
          const double s = ((pu - a[u]) * (c[v] - a[v]) - (c[u] - a[u]) * (pv - a[v])) / det;
          const double t = ((b[u] - a[u]) * (pv - a[v]) - (pu - a[u]) * (b[v] - a[v])) / det;
          if (s < 0.0 || t < 0.0 || s + t > 1.0) continue;
          hits[static_cast<std::size_t>(j + cells[u] * k)].push_back(
              a[axis] + s * (b[axis] - a[axis]) + t * (c[axis] - a[axis]));
        }
      }
    }
    for (int j = 0; j < cells[u]; ++j) {
      for (int k = 0; k < cells[v]; ++k) {
        std::vector<double>& row = hits[static_cast<std::size_t>(j + cells[u] * k)];
        std::sort(row.begin(), row.end());
        std::size_t crossed = 0;
        for (int i = 0; i < cells[axis]; ++i) {
          const double position = (i + 0.5) * h;
          while (crossed < row.size() && row[crossed] < position) ++crossed;
          if (crossed % 2 == 1) {
            Eigen::Vector3i cell;
            cell[axis] = i;
            cell[u] = j;
            cell[v] = k;
            ++votes[cellIndex(cell)];
          }
        }
      }
    }
  }
  return votes;
}

}  // namespace

TetMesh meshInterior(const TriangleSurface& surface, const LatticeOptions& options) {
  const double h = options.edgeLength_m;
  if (!(h > 0.0) || !std::isfinite(h))
    throw std::invalid_argument("the lattice edge length must be > 0");
  if (surface.triangleCount() == 0) throw std::invalid_argument("the surface has no triangles");
  const Eigen::Vector3d lower = surface.vertices_m.rowwise().minCoeff();
  const Eigen::Vector3d upper = surface.vertices_m.rowwise().maxCoeff();
  // One cell of margin around the box, so cells holding surface vertices are never cut off.
  const Eigen::Vector3d origin = lower.array() - h;
  const Eigen::Vector3i cells = (((upper - lower).array() / h).ceil() + 2.0).cast<int>();
  if (static_cast<double>(cells.cast<double>().prod()) > 2e7) {
    throw std::invalid_argument(
        "the lattice would have over 20 million cells; use a larger edge length");
  }
  std::vector<int> votes = insideVotes(surface, origin, h, cells);
  std::vector<char> keep(votes.size(), 0);
  for (std::size_t c = 0; c < votes.size(); ++c) keep[c] = votes[c] >= 2 ? 1 : 0;

  // Tets of the kept cells from the full block's split, then unused nodes dropped.
  const TetMesh block = makeBlockMesh(cells.cast<double>() * h, cells, origin);
  std::vector<int> keptTets;
  for (Eigen::Index t = 0; t < block.tetCount(); ++t) {
    if (keep[static_cast<std::size_t>(t / 6)] != 0) keptTets.push_back(static_cast<int>(t));
  }
  if (keptTets.empty()) throw std::invalid_argument("no lattice cell lies inside the surface");
  std::vector<int> newIndex(static_cast<std::size_t>(block.nodeCount()), -1);
  int nodes = 0;
  TetMesh mesh;
  mesh.tets.resize(4, static_cast<Eigen::Index>(keptTets.size()));
  for (std::size_t i = 0; i < keptTets.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      int& index = newIndex[static_cast<std::size_t>(block.tets(k, keptTets[i]))];
      if (index < 0) index = nodes++;
      mesh.tets(k, static_cast<Eigen::Index>(i)) = index;
    }
  }
  mesh.nodes_m.resize(3, nodes);
  for (Eigen::Index v = 0; v < block.nodeCount(); ++v) {
    if (newIndex[static_cast<std::size_t>(v)] >= 0)
      mesh.nodes_m.col(newIndex[static_cast<std::size_t>(v)]) = block.nodes_m.col(v);
  }
  return mesh;
}

double edgeLengthForSpringCount(const TriangleSurface& surface, int targetSprings) {
  if (targetSprings < 6) throw std::invalid_argument("a target of fewer than 6 springs is no mesh");
  const double volume = std::abs(enclosedVolume(surface));
  // About 7 springs per cube: start from h^3 = 7 V / N, then correct by measuring twice.
  double h = std::cbrt(7.0 * std::max(volume, 1e-12) / targetSprings);
  for (int round = 0; round < 3; ++round) {
    const TetMesh mesh = meshInterior(surface, {h});
    const auto springs = static_cast<double>(countUniqueEdges(mesh));
    h *= std::cbrt(springs / targetSprings);
  }
  return h;
}

}  // namespace tissuesim
