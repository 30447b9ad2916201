// SPDX-License-Identifier: Apache-2.0
#include "fem/StrainCells.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/LU>

#include "mesh/TetMesh.h"

namespace tissuesim {

namespace {

/// Each tet's rest volume and shape gradients (F_t = sum_c x_c g_c,t^T).
struct TetShapes {
  std::vector<double> volume_m3;
  Eigen::Matrix<double, 12, Eigen::Dynamic> gradients_1_m;
};

TetShapes tetShapes(const Eigen::Matrix3Xd& rest, const Eigen::Matrix4Xi& tets) {
  TetShapes shapes;
  shapes.volume_m3.resize(static_cast<std::size_t>(tets.cols()));
  shapes.gradients_1_m.resize(12, tets.cols());
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    Eigen::Matrix3d dm;
    for (int c = 1; c < 4; ++c) dm.col(c - 1) = rest.col(tets(c, t)) - rest.col(tets(0, t));
    const double volume = dm.determinant() / 6.0;
    if (!(volume > 0.0)) {
      throw std::invalid_argument("tet " + std::to_string(t) +
                                  " is not positively oriented at rest");
    }
    shapes.volume_m3[static_cast<std::size_t>(t)] = volume;
    // F = Ds Dm^-1: g_1..g_3 are Dm^-1's rows, g_0 minus their sum.
    const Eigen::Matrix3d inverse = dm.inverse();
    for (int c = 1; c < 4; ++c) {
      shapes.gradients_1_m.block<3, 1>(3 * c, t) = inverse.row(c - 1).transpose();
    }
    shapes.gradients_1_m.block<3, 1>(0, t) = -inverse.colwise().sum().transpose();
  }
  return shapes;
}

/// Builds the cells one at a time from their (tet, share) parts.
class CellBuilder {
 public:
  CellBuilder(const Eigen::Matrix4Xi& tets, const TetShapes& shapes)
      : m_tets(tets), m_shapes(shapes) {
    m_cells.start.push_back(0);
  }

  void add(const std::vector<std::pair<int, double>>& parts) {
    const auto first = static_cast<std::ptrdiff_t>(m_cells.nodes.size());
    double volume = 0.0;
    for (const auto& [t, share] : parts) {
      volume += share * m_shapes.volume_m3[static_cast<std::size_t>(t)];
      for (int c = 0; c < 4; ++c) m_cells.nodes.push_back(m_tets(c, t));
    }
    std::sort(m_cells.nodes.begin() + first, m_cells.nodes.end());
    m_cells.nodes.erase(std::unique(m_cells.nodes.begin() + first, m_cells.nodes.end()),
                        m_cells.nodes.end());
    m_gradients.resize(m_cells.nodes.size(), Eigen::Vector3d::Zero());
    for (const auto& [t, share] : parts) {
      const double weight = share * m_shapes.volume_m3[static_cast<std::size_t>(t)] / volume;
      for (int c = 0; c < 4; ++c) {
        const auto at =
            std::lower_bound(m_cells.nodes.begin() + first, m_cells.nodes.end(), m_tets(c, t)) -
            m_cells.nodes.begin();
        m_gradients[static_cast<std::size_t>(at)] +=
            weight * m_shapes.gradients_1_m.block<3, 1>(3 * c, t);
      }
    }
    m_volumes.push_back(volume);
    m_cells.start.push_back(static_cast<int>(m_cells.nodes.size()));
  }

  StrainCells finish() {
    m_cells.gradients_1_m.resize(3, static_cast<Eigen::Index>(m_gradients.size()));
    for (std::size_t e = 0; e < m_gradients.size(); ++e) {
      m_cells.gradients_1_m.col(static_cast<Eigen::Index>(e)) = m_gradients[e];
    }
    m_cells.volume_m3 = Eigen::Map<const Eigen::VectorXd>(
        m_volumes.data(), static_cast<Eigen::Index>(m_volumes.size()));
    return std::move(m_cells);
  }

 private:
  const Eigen::Matrix4Xi& m_tets;
  const TetShapes& m_shapes;
  StrainCells m_cells;
  std::vector<Eigen::Vector3d> m_gradients;
  std::vector<double> m_volumes;
};

}  // namespace

StrainCells faceStrainCells(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets) {
  const TetShapes shapes = tetShapes(restPositions_m, tets);
  // Each tet's four faces, keyed by their sorted corners; a face shared by two tets is one cell.
  std::vector<std::pair<std::array<int, 3>, int>> faces;
  faces.reserve(4 * static_cast<std::size_t>(tets.cols()));
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int omitted = 0; omitted < 4; ++omitted) {
      std::array<int, 3> key{};
      int k = 0;
      for (int c = 0; c < 4; ++c) {
        if (c != omitted) key[static_cast<std::size_t>(k++)] = tets(c, t);
      }
      std::sort(key.begin(), key.end());
      faces.emplace_back(key, static_cast<int>(t));
    }
  }
  std::sort(faces.begin(), faces.end());
  CellBuilder builder(tets, shapes);
  std::vector<std::pair<int, double>> parts;
  for (std::size_t f = 0; f < faces.size();) {
    parts.clear();
    std::size_t g = f;
    for (; g < faces.size() && faces[g].first == faces[f].first; ++g) {
      parts.emplace_back(faces[g].second, 0.25);
    }
    builder.add(parts);
    f = g;
  }
  return builder.finish();
}

StrainCells nodeStrainCells(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets) {
  const TetShapes shapes = tetShapes(restPositions_m, tets);
  const NodeTetIncidence incidence = nodeTetIncidence(tets, restPositions_m.cols());
  CellBuilder builder(tets, shapes);
  std::vector<std::pair<int, double>> parts;
  for (std::size_t a = 0; a + 1 < incidence.start.size(); ++a) {
    if (incidence.start[a] == incidence.start[a + 1]) continue;
    parts.clear();
    for (int e = incidence.start[a]; e < incidence.start[a + 1]; ++e) {
      parts.emplace_back(incidence.entries[static_cast<std::size_t>(e)] / 4, 0.25);
    }
    builder.add(parts);
  }
  return builder.finish();
}

}  // namespace tissuesim
