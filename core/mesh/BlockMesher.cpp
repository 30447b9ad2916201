// SPDX-License-Identifier: Apache-2.0
#include "mesh/BlockMesher.h"

#include <algorithm>
#include <array>
#include <functional>
#include <stdexcept>

namespace tissuesim {

TetMesh makeBlockMesh(const Eigen::Vector3d& size_m, const Eigen::Vector3i& cells,
                      const Eigen::Vector3d& origin_m) {
  if ((size_m.array() <= 0.0).any() || !size_m.allFinite()) {
    throw std::invalid_argument("a block needs positive, finite edge lengths");
  }
  if ((cells.array() < 1).any())
    throw std::invalid_argument("a block needs at least one cell per axis");
  std::array<std::vector<double>, 3> lines;
  for (int axis = 0; axis < 3; ++axis) {
    for (int i = 0; i <= cells[axis]; ++i)
      lines[static_cast<std::size_t>(axis)].push_back(origin_m[axis] +
                                                      size_m[axis] * i / cells[axis]);
  }
  return makeRectilinearMesh(lines[0], lines[1], lines[2]);
}

TetMesh makeRectilinearMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                            const std::vector<double>& zs) {
  for (const std::vector<double>* line : {&xs, &ys, &zs}) {
    // less_equal: a repeated coordinate counts as out of order.
    if (line->size() < 2 || !std::is_sorted(line->begin(), line->end(), std::less_equal<>())) {
      throw std::invalid_argument(
          "a rectilinear mesh needs at least two increasing coordinates "
          "per axis");
    }
  }
  const Eigen::Vector3i cells(static_cast<int>(xs.size()) - 1, static_cast<int>(ys.size()) - 1,
                              static_cast<int>(zs.size()) - 1);
  const int nx = cells.x() + 1;
  const int ny = cells.y() + 1;
  const int nz = cells.z() + 1;
  const auto nodeIndex = [&](int i, int j, int k) { return i + nx * (j + ny * k); };

  TetMesh mesh;
  mesh.nodes_m.resize(3, static_cast<Eigen::Index>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        mesh.nodes_m.col(nodeIndex(i, j, k)) =
            Eigen::Vector3d(xs[static_cast<std::size_t>(i)], ys[static_cast<std::size_t>(j)],
                            zs[static_cast<std::size_t>(k)]);
      }
    }
  }

  // Kuhn: one tet per ordering of the three axes, walking from corner (0,0,0) to (1,1,1).
  const std::array<std::array<int, 3>, 6> orders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  mesh.tets.resize(4, static_cast<Eigen::Index>(6) * cells.prod());
  Eigen::Index t = 0;
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      for (int i = 0; i < cells.x(); ++i) {
        for (const auto& order : orders) {
          std::array<int, 3> corner = {i, j, k};
          std::array<int, 4> tet{};
          tet[0] = nodeIndex(corner[0], corner[1], corner[2]);
          for (int step = 0; step < 3; ++step) {
            ++corner[static_cast<std::size_t>(order[static_cast<std::size_t>(step)])];
            tet[static_cast<std::size_t>(step) + 1] = nodeIndex(corner[0], corner[1], corner[2]);
          }
          if (signedTetVolume(mesh.nodes_m.col(tet[0]), mesh.nodes_m.col(tet[1]),
                              mesh.nodes_m.col(tet[2]), mesh.nodes_m.col(tet[3])) < 0.0) {
            std::swap(tet[2], tet[3]);
          }
          mesh.tets.col(t++) << tet[0], tet[1], tet[2], tet[3];
        }
      }
    }
  }
  return mesh;
}

}  // namespace tissuesim
