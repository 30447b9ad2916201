#include "mesh/SurfaceEmbedding.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

namespace tissuesim {
namespace {

/// Barycentric weights of p in tet t (4, summing to 1; all >= 0 inside).
Eigen::Vector4d barycentric(const TetMesh& mesh, Eigen::Index t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = mesh.nodes_m.col(mesh.tets(0, t));
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = mesh.nodes_m.col(mesh.tets(k + 1, t)) - a;
  const Eigen::Vector3d w = edges.partialPivLu().solve(p - a);
  return {1.0 - w.sum(), w.x(), w.y(), w.z()};
}

}  // namespace

SurfaceEmbedding::SurfaceEmbedding(const TetMesh& mesh, const Eigen::Matrix3Xd& surfaceVertices_m)
    : m_nodes(4, surfaceVertices_m.cols()), m_weights(4, surfaceVertices_m.cols()) {
  // Bin tets by bounding box on a grid of about the mean tet size.
  const Eigen::Vector3d lower = mesh.nodes_m.rowwise().minCoeff();
  const Eigen::Vector3d upper = mesh.nodes_m.rowwise().maxCoeff();
  const double cell = std::max(
      1e-9, std::cbrt((upper - lower).prod() / std::max<Eigen::Index>(1, mesh.tetCount())) * 2.0);
  const Eigen::Vector3i cells = (((upper - lower).array() / cell).floor() + 1.0).cast<int>();
  const auto binOf = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3i c =
        ((p - lower).array() / cell).floor().cast<int>().cwiseMax(0).cwiseMin(cells.array() - 1);
    return static_cast<long long>(c.x()) +
           cells.x() * (static_cast<long long>(c.y()) + cells.y() * static_cast<long long>(c.z()));
  };
  std::unordered_map<long long, std::vector<int>> bins;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    Eigen::Vector3d lo = mesh.nodes_m.col(mesh.tets(0, t)), hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(mesh.nodes_m.col(mesh.tets(k, t)));
      hi = hi.cwiseMax(mesh.nodes_m.col(mesh.tets(k, t)));
    }
    const Eigen::Vector3i a =
        ((lo - lower).array() / cell).floor().cast<int>().cwiseMax(0).cwiseMin(cells.array() - 1);
    const Eigen::Vector3i b =
        ((hi - lower).array() / cell).floor().cast<int>().cwiseMax(0).cwiseMin(cells.array() - 1);
    for (int x = a.x(); x <= b.x(); ++x)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int z = a.z(); z <= b.z(); ++z)
          bins[static_cast<long long>(x) +
               cells.x() * (static_cast<long long>(y) + cells.y() * static_cast<long long>(z))]
              .push_back(static_cast<int>(t));
  }

  for (Eigen::Index v = 0; v < surfaceVertices_m.cols(); ++v) {
    const Eigen::Vector3d p = surfaceVertices_m.col(v);
    Eigen::Index best = -1;
    Eigen::Vector4d bestWeights = Eigen::Vector4d::Zero();
    double bestMin = -std::numeric_limits<double>::infinity();
    const auto consider = [&](Eigen::Index t) {
      const Eigen::Vector4d w = barycentric(mesh, t, p);
      if (w.minCoeff() > bestMin) {
        bestMin = w.minCoeff();
        best = t;
        bestWeights = w;
      }
    };
    if (const auto found = bins.find(binOf(p)); found != bins.end()) {
      for (const int t : found->second) consider(t);
    }
    if (bestMin < -1e-12) {
      // Outside every tet of its bin: the tet least outside among the neighbouring bins, and
      // only if there are none, among all tets.
      const Eigen::Vector3i c = ((p - lower).array() / cell).floor().cast<int>();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const Eigen::Vector3i n = (c + Eigen::Vector3i(dx, dy, dz))
                                          .cwiseMax(0)
                                          .cwiseMin((cells.array() - 1).matrix());
            const auto found = bins.find(static_cast<long long>(n.x()) +
                                         cells.x() * (static_cast<long long>(n.y()) +
                                                      cells.y() * static_cast<long long>(n.z())));
            if (found == bins.end()) continue;
            for (const int t : found->second) consider(t);
          }
      if (best < 0) {
        for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) consider(t);
      }
    }
    for (int k = 0; k < 4; ++k) m_nodes(k, v) = mesh.tets(k, best);
    m_weights.col(v) = bestWeights;
    if (bestMin < -1e-12) {
      ++m_outsideCount;
      Eigen::Vector3d inside = Eigen::Vector3d::Zero();
      const Eigen::Vector4d clamped = bestWeights.cwiseMax(0.0) / bestWeights.cwiseMax(0.0).sum();
      for (int k = 0; k < 4; ++k) inside += clamped[k] * mesh.nodes_m.col(mesh.tets(k, best));
      m_maxOutsideDistance_m = std::max(m_maxOutsideDistance_m, (inside - p).norm());
    }
  }
}

void SurfaceEmbedding::apply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& surface) const {
  for (Eigen::Index v = 0; v < m_nodes.cols(); ++v) {
    surface.col(v) =
        m_weights(0, v) * x.col(m_nodes(0, v)) + m_weights(1, v) * x.col(m_nodes(1, v)) +
        m_weights(2, v) * x.col(m_nodes(2, v)) + m_weights(3, v) * x.col(m_nodes(3, v));
  }
}

}  // namespace tissuesim
