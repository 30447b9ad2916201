// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetLocator.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuesim {

TetLocator::TetLocator(const TetMesh& mesh) : m_mesh(mesh) {
  m_inverseEdges.resize(static_cast<std::size_t>(mesh.tetCount()));
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    const Eigen::Vector3d a = mesh.nodes_m.col(mesh.tets(0, t));
    Eigen::Matrix3d edges;
    for (int k = 0; k < 3; ++k) edges.col(k) = mesh.nodes_m.col(mesh.tets(k + 1, t)) - a;
    // A degenerate tet (validated meshes have none) gets NaN weights and is never chosen.
    m_inverseEdges[static_cast<std::size_t>(t)] = edges.inverse();
  }
  m_lower = mesh.nodes_m.rowwise().minCoeff();
  const Eigen::Vector3d upper = mesh.nodes_m.rowwise().maxCoeff();
  m_cell_m = std::max(
      1e-9, std::cbrt((upper - m_lower).prod() / std::max<Eigen::Index>(1, mesh.tetCount())) * 2.0);
  m_cells = (((upper - m_lower).array() / m_cell_m).floor() + 1.0).cast<int>();
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    Eigen::Vector3d lo = mesh.nodes_m.col(mesh.tets(0, t)), hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(mesh.nodes_m.col(mesh.tets(k, t)));
      hi = hi.cwiseMax(mesh.nodes_m.col(mesh.tets(k, t)));
    }
    const Eigen::Vector3i a = cellOf(lo), b = cellOf(hi);
    for (int x = a.x(); x <= b.x(); ++x)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int z = a.z(); z <= b.z(); ++z)
          m_bins[keyOf({x, y, z})].push_back(static_cast<int>(t));
  }
}

Eigen::Vector3i TetLocator::cellOf(const Eigen::Vector3d& p) const {
  return ((p - m_lower).array() / m_cell_m)
      .floor()
      .cast<int>()
      .cwiseMax(0)
      .cwiseMin(m_cells.array() - 1);
}

long long TetLocator::keyOf(const Eigen::Vector3i& cell) const {
  return static_cast<long long>(cell.x()) +
         m_cells.x() *
             (static_cast<long long>(cell.y()) + m_cells.y() * static_cast<long long>(cell.z()));
}

Eigen::Vector4d TetLocator::weightsIn(int t, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = m_mesh.nodes_m.col(m_mesh.tets(0, t));
  const Eigen::Vector3d w = m_inverseEdges[static_cast<std::size_t>(t)] * (p - a);
  return {1.0 - w.sum(), w.x(), w.y(), w.z()};
}

TetLocation TetLocator::locateAmong(const std::vector<int>& tets, const Eigen::Vector3d& p) const {
  TetLocation best;
  double bestMin = -std::numeric_limits<double>::infinity();
  for (const int t : tets) {
    const Eigen::Vector4d w = weightsIn(t, p);
    if (w.minCoeff() > bestMin) {
      bestMin = w.minCoeff();
      best = {t, w};
    }
  }
  return best;
}

void TetLocator::tetsNear(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                          std::vector<int>& tets) const {
  const std::size_t first = tets.size();
  const Eigen::Vector3i a = cellOf(lower), b = cellOf(upper);
  for (int x = a.x(); x <= b.x(); ++x)
    for (int y = a.y(); y <= b.y(); ++y)
      for (int z = a.z(); z <= b.z(); ++z) {
        const auto found = m_bins.find(keyOf({x, y, z}));
        if (found != m_bins.end())
          tets.insert(tets.end(), found->second.begin(), found->second.end());
      }
  std::sort(tets.begin() + static_cast<std::ptrdiff_t>(first), tets.end());
  tets.erase(std::unique(tets.begin() + static_cast<std::ptrdiff_t>(first), tets.end()),
             tets.end());
}

TetLocation TetLocator::locate(const Eigen::Vector3d& p) const {
  std::vector<int> tets;
  tetsNear(p, p, tets);
  TetLocation best = tets.empty() ? TetLocation{} : locateAmong(tets, p);
  if (best.tet >= 0 && best.isInside()) return best;
  // Outside every tet of its bin: the tet least outside among the neighbouring bins, and only
  // if there are none, among all tets.
  tets.clear();
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(m_cell_m);
  tetsNear(p - reach, p + reach, tets);
  if (tets.empty()) {
    tets.resize(static_cast<std::size_t>(m_mesh.tetCount()));
    for (std::size_t t = 0; t < tets.size(); ++t) tets[t] = static_cast<int>(t);
  }
  return locateAmong(tets, p);
}

}  // namespace tissuesim
