// SPDX-License-Identifier: Apache-2.0
#include "fem/QuadraticTetWeight.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

namespace tissuesim {

NodalLoads quadraticTetWeight(const QuadraticTetMesh& mesh, double density_kg_m3,
                              const Eigen::Vector3d& gravity_m_s2) {
  if (!(density_kg_m3 > 0.0) || !std::isfinite(density_kg_m3) || !gravity_m_s2.allFinite())
    throw std::invalid_argument("the body's weight: density must be positive and finite, g finite");
  NodalLoads loads;
  loads.nodes.resize(static_cast<std::size_t>(mesh.nodeCount()));
  std::iota(loads.nodes.begin(), loads.nodes.end(), 0);
  loads.forces_N.setZero(3, mesh.nodeCount());
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    const Eigen::Vector3d x0 = mesh.nodes_m.col(mesh.tets(0, t));
    Eigen::Matrix3d edges;
    for (int c = 0; c < 3; ++c) edges.col(c) = mesh.nodes_m.col(mesh.tets(c + 1, t)) - x0;
    const Eigen::Vector3d weight_N = density_kg_m3 * (edges.determinant() / 6.0) * gravity_m_s2;
    for (int a = 0; a < 4; ++a) loads.forces_N.col(mesh.tets(a, t)) -= weight_N / 20.0;
    for (int a = 4; a < 10; ++a) loads.forces_N.col(mesh.tets(a, t)) += weight_N / 5.0;
  }
  return loads;
}

}  // namespace tissuesim
