// SPDX-License-Identifier: Apache-2.0
#include "mesh/SurfaceEmbedding.h"

#include <algorithm>

#include "mesh/TetLocator.h"

namespace tissuesim {

SurfaceEmbedding::SurfaceEmbedding(const TetMesh& mesh, const Eigen::Matrix3Xd& surfaceVertices_m)
    : m_nodes(4, surfaceVertices_m.cols()), m_weights(4, surfaceVertices_m.cols()) {
  const TetLocator locator(mesh);
  for (Eigen::Index v = 0; v < surfaceVertices_m.cols(); ++v) {
    const Eigen::Vector3d p = surfaceVertices_m.col(v);
    const TetLocation found = locator.locate(p);
    m_tets.push_back(found.tet);
    for (int k = 0; k < 4; ++k) m_nodes(k, v) = mesh.tets(k, found.tet);
    m_weights.col(v) = found.weights;
    if (!found.isInside()) {
      ++m_outsideCount;
      Eigen::Vector3d inside = Eigen::Vector3d::Zero();
      const Eigen::Vector4d clamped = clampedToTet(found.weights);
      for (int k = 0; k < 4; ++k) inside += clamped[k] * mesh.nodes_m.col(mesh.tets(k, found.tet));
      m_maxOutsideDistance_m = std::max(m_maxOutsideDistance_m, (inside - p).norm());
    }
  }
}

void SurfaceEmbedding::apply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& surface) const {
  for (Eigen::Index v = 0; v < m_nodes.cols(); ++v) surface.col(v) = position(v, x);
}

void SurfaceEmbedding::interpolate(const Eigen::VectorXd& nodeValues,
                                   Eigen::VectorXd& values) const {
  values.resize(m_nodes.cols());  // a no-op once sized
  for (Eigen::Index v = 0; v < m_nodes.cols(); ++v) {
    values[v] =
        m_weights(0, v) * nodeValues[m_nodes(0, v)] + m_weights(1, v) * nodeValues[m_nodes(1, v)] +
        m_weights(2, v) * nodeValues[m_nodes(2, v)] + m_weights(3, v) * nodeValues[m_nodes(3, v)];
  }
}

}  // namespace tissuesim
