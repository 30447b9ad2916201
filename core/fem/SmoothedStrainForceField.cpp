// SPDX-License-Identifier: Apache-2.0
#include "fem/SmoothedStrainForceField.h"

#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "fem/IsochoricMaterialPoint.h"
#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

SmoothedStrainForceField::SmoothedStrainForceField(StrainCells cells, Eigen::Index nodeCount,
                                                   const StrainEnergy& energy)
    : m_cells(std::move(cells)), m_energy(energy), m_limitShift(energy.usableInvariantShift()) {
  const Eigen::Index cellCount = m_cells.cellCount();
  // Each node's entries, in entry order.
  m_entryCell.resize(m_cells.nodes.size());
  m_nodeEntryStart.assign(static_cast<std::size_t>(nodeCount) + 1, 0);
  for (Eigen::Index c = 0; c < cellCount; ++c) {
    const auto u = static_cast<std::size_t>(c);
    for (int e = m_cells.start[u]; e < m_cells.start[u + 1]; ++e) {
      m_entryCell[static_cast<std::size_t>(e)] = static_cast<int>(c);
      ++m_nodeEntryStart[static_cast<std::size_t>(m_cells.nodes[static_cast<std::size_t>(e)]) + 1];
    }
  }
  for (std::size_t j = 0; j < static_cast<std::size_t>(nodeCount); ++j) {
    m_nodeEntryStart[j + 1] += m_nodeEntryStart[j];
  }
  m_nodeEntries.resize(m_cells.nodes.size());
  std::vector<int> fill(m_nodeEntryStart.begin(), m_nodeEntryStart.end() - 1);
  for (std::size_t e = 0; e < m_cells.nodes.size(); ++e) {
    m_nodeEntries[static_cast<std::size_t>(fill[static_cast<std::size_t>(m_cells.nodes[e])]++)] =
        static_cast<int>(e);
  }

  // K's rows, and where each pair of a cell's nodes goes in them.
  m_rows = NodeRowStiffness(cellNeighbours(m_cells.start, m_cells.nodes, nodeCount));
  m_pairStart.resize(m_cells.nodes.size());
  for (Eigen::Index c = 0; c < cellCount; ++c) {
    const auto u = static_cast<std::size_t>(c);
    for (int e = m_cells.start[u]; e < m_cells.start[u + 1]; ++e) {
      m_pairStart[static_cast<std::size_t>(e)] = static_cast<int>(m_pairSlot.size());
      for (int h = m_cells.start[u]; h < m_cells.start[u + 1]; ++h) {
        m_pairSlot.push_back(m_rows.entry(m_cells.nodes[static_cast<std::size_t>(e)],
                                          m_cells.nodes[static_cast<std::size_t>(h)]));
      }
    }
  }

  m_cellStress_N_m2.setZero(9, cellCount);
  m_boundScale.setZero(cellCount);
  m_tangents.setZero(81, cellCount);
  for (int p = 0; p <= kParts; ++p) m_bounds[static_cast<std::size_t>(p)] = nodeCount * p / kParts;
}

Eigen::Matrix2Xi SmoothedStrainForceField::couplings() const {
  return starCouplings(NodeStars{m_cells.start, m_cells.nodes});
}

Eigen::Matrix3d SmoothedStrainForceField::deformationGradient(const Eigen::Matrix3Xd& x,
                                                              Eigen::Index c) const {
  const auto u = static_cast<std::size_t>(c);
  Eigen::Matrix3d f = Eigen::Matrix3d::Zero();
  for (int e = m_cells.start[u]; e < m_cells.start[u + 1]; ++e) {
    f += x.col(m_cells.nodes[static_cast<std::size_t>(e)]) *
         m_cells.gradients_1_m.col(e).transpose();
  }
  return f;
}

double SmoothedStrainForceField::energy(const Eigen::Matrix3Xd& x) const {
  double total = 0.0;
  for (Eigen::Index c = 0; c < m_cells.cellCount(); ++c) {
    const Eigen::Matrix3d f = deformationGradient(x, c);
    const double j = f.determinant();
    if (!(j > 0.0)) continue;
    const double shift = std::pow(j, -2.0 / 3.0) * f.squaredNorm() - 3.0;
    total += m_cells.volume_m3[c] *
             continuedIsochoricEnergy(m_energy, shift, m_limitShift, /*withEnergy=*/true).energy;
  }
  return total;
}

void SmoothedStrainForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                         const ForcePass& pass, ForceReport& report) const {
  NodeRowStiffness::Blocks* const rowBlocks =
      pass.stiffness == StiffnessSlot::None ? nullptr : &m_rows.slot(pass.stiffness);
  const bool needsTangent = rowBlocks != nullptr || pass.nodeStiffness != nullptr;

  // Each cell's F_c, V0_c P_c and V0_c T_c.
  forEachNodeRange(
      m_pool, m_cells.cellCount(),
      [&](int range, Eigen::Index begin, Eigen::Index end) {
        TetFieldReport seen;
        for (Eigen::Index c = begin; c < end; ++c) {
          Eigen::Map<Eigen::Matrix3d> stress(m_cellStress_N_m2.col(c).data());
          stress.setZero();
          if (needsTangent) m_tangents.col(c).setZero();
          m_boundScale[c] = 0.0;
          const Eigen::Matrix3d deformation = deformationGradient(x, c);
          const double j = deformation.determinant();
          if (!(j > 0.0)) {
            ++seen.invertedCount;
            continue;
          }
          const double i1 = deformation.squaredNorm();
          const double scale = std::pow(j, -2.0 / 3.0);  // J^(-2/3)
          const double shift = scale * i1 - 3.0;
          if (shift > m_limitShift) ++seen.beyondRangeCount;
          const EnergyInI1 w =
              continuedIsochoricEnergy(m_energy, shift, m_limitShift, /*withEnergy=*/false);
          // A = dI1bar/dF; P = W_T' A.
          const Eigen::Matrix3d a =
              scale * (2.0 * deformation - (2.0 / 3.0) * i1 * deformation.inverse().transpose());
          const double volume = m_cells.volume_m3[c];
          stress = (volume * w.dEnergy) * a;
          if (!needsTangent) continue;
          const StressTangent tangent =
              volume * (pass.isProjected
                            ? projectedIsochoricTangent(deformation, w.dEnergy, w.d2Energy)
                            : exactIsochoricTangent(deformation, a, i1, scale, w));
          Eigen::Map<StressTangent>(m_tangents.col(c).data()) = tangent;
          if (pass.nodeStiffness != nullptr) {
            const auto u = static_cast<std::size_t>(c);
            m_boundScale[c] =
                tangent.norm() *
                m_cells.gradients_1_m
                    .middleCols(m_cells.start[u], m_cells.start[u + 1] - m_cells.start[u])
                    .norm();
          }
        }
        m_rangeReport[static_cast<std::size_t>(range)] = seen;
      },
      0);

  // f_j = -sum over the cells c that hold j of V0_c P_c G_cj; K_jd = sum over the same cells of
  // sum_JL V0_c T_(iJ)(kL) G_cj,J G_cd,L for each node d of c.
  forEachNodeRange(
      m_pool, x.cols(),
      [&](int, Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index j = begin; j < end; ++j) {
          const auto u = static_cast<std::size_t>(j);
          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
          double bound = 0.0;
          if (rowBlocks != nullptr) m_rows.clearRow(*rowBlocks, j);
          for (int n = m_nodeEntryStart[u]; n < m_nodeEntryStart[u + 1]; ++n) {
            const int e = m_nodeEntries[static_cast<std::size_t>(n)];
            const int c = m_entryCell[static_cast<std::size_t>(e)];
            const auto g = m_cells.gradients_1_m.col(e);
            sum += Eigen::Map<const Eigen::Matrix3d>(m_cellStress_N_m2.col(c).data()) * g;
            if (pass.nodeStiffness != nullptr) bound += m_boundScale[c] * g.norm();
            if (rowBlocks != nullptr) addCellRow(c, e, *rowBlocks);
          }
          f.col(j) -= sum;
          if (pass.nodeStiffness != nullptr) (*pass.nodeStiffness)[j] += bound;
        }
      },
      0);

  for (const TetFieldReport& seen : m_rangeReport) report.tets.include(seen);
}

void SmoothedStrainForceField::addCellRow(Eigen::Index c, int e,
                                          NodeRowStiffness::Blocks& rowBlocks) const {
  // tg(i, 3 k + L) = sum_J T_(iJ)(kL) G_cb,J, b entry e's node; then block (i, k) of each node d
  // of the cell is sum_L tg(i, 3 k + L) G_cd,L.
  const Eigen::Map<const StressTangent> tangent(m_tangents.col(c).data());
  const Eigen::Vector3d g = m_cells.gradients_1_m.col(e);
  Eigen::Matrix<double, 3, 9> tg;
  for (int i = 0; i < 3; ++i) {
    tg.row(i) =
        g(0) * tangent.row(3 * i) + g(1) * tangent.row(3 * i + 1) + g(2) * tangent.row(3 * i + 2);
  }
  const auto u = static_cast<std::size_t>(c);
  const int* slot = &m_pairSlot[static_cast<std::size_t>(m_pairStart[static_cast<std::size_t>(e)])];
  for (int h = m_cells.start[u]; h < m_cells.start[u + 1]; ++h) {
    const Eigen::Vector3d gd = m_cells.gradients_1_m.col(h);
    Eigen::Map<Eigen::Matrix3d> block(rowBlocks.col(*slot++).data());
    for (int k = 0; k < 3; ++k) {
      block.col(k) += tg.middleCols<3>(3 * k) * gd;
    }
  }
}

void SmoothedStrainForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  m_rows.addProductWork(nodeWork);
}

void SmoothedStrainForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  const auto p = static_cast<std::size_t>(part);
  m_rows.addProduct(m_bounds[p], m_bounds[p + 1], x, y);
}

void SmoothedStrainForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  m_rows.addDiagonalBlock(j, block);
}

void SmoothedStrainForceField::addStiffness(NodeBlockMatrix& matrix) const {
  m_rows.addStiffness(matrix);
}

}  // namespace tissuesim
