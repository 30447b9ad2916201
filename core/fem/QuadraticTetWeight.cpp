// SPDX-License-Identifier: Apache-2.0
#include "fem/QuadraticTetWeight.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

#include <Eigen/LU>

#include "fem/QuadraticTetShape.h"

namespace tissuesim {

NodalLoads quadraticTetWeight(const QuadraticTetMesh& mesh, double density_kg_m3,
                              const Eigen::Vector3d& gravity_m_s2) {
  if (!(density_kg_m3 > 0.0) || !std::isfinite(density_kg_m3) || !gravity_m_s2.allFinite())
    throw std::invalid_argument("the body's weight: density must be positive and finite, g finite");
  NodalLoads loads;
  loads.nodes.resize(static_cast<std::size_t>(mesh.nodeCount()));
  std::iota(loads.nodes.begin(), loads.nodes.end(), 0);
  loads.forces_N.setZero(3, mesh.nodeCount());
  const auto rule = tetQuadratureDegree3();
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (const TetQuadraturePoint& point : rule) {
      const Eigen::Vector4d l(1.0 - point.xi.sum(), point.xi.x(), point.xi.y(), point.xi.z());
      const Eigen::Matrix<double, 10, 1> shares = quadraticTetShapeValues(l);
      const double volume_m3 = point.weight * quadraticTetJacobian(mesh, t, point.xi).determinant();
      for (int a = 0; a < 10; ++a)
        loads.forces_N.col(mesh.tets(a, t)) +=
            (density_kg_m3 * shares(a) * volume_m3) * gravity_m_s2;
    }
  }
  return loads;
}

}  // namespace tissuesim
