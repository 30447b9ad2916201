#include "mesh/BlockMesher.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace tissuesim {

TetMesh makeBlockMesh(const Eigen::Vector3d& size_m, const Eigen::Vector3i& cells,
                      const Eigen::Vector3d& origin_m) {
  if ((size_m.array() <= 0.0).any() || !size_m.allFinite()) {
    throw std::invalid_argument("a block needs positive, finite edge lengths");
  }
  if ((cells.array() < 1).any())
    throw std::invalid_argument("a block needs at least one cell per axis");
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
            origin_m + Eigen::Vector3d(size_m.x() * i / cells.x(), size_m.y() * j / cells.y(),
                                       size_m.z() * k / cells.z());
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
