// SPDX-License-Identifier: Apache-2.0
#include "fem/SmoothedStrainForceField.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "fem/IsochoricMaterialPoint.h"
#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

namespace {

using RowMajor3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;  // F_iJ at 3 i + J

/// The 3x3 block sum_JL T_(iJ)(kL) g_J h_L of a cell's tangent.
Eigen::Matrix3d contract(const double* tangent, const Eigen::Vector3d& g,
                         const Eigen::Vector3d& h) {
  const Eigen::Map<const StressTangent> t(tangent);
  Eigen::Matrix3d block;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) block(i, k) = g.dot(t.block<3, 3>(3 * i, 3 * k) * h);
  }
  return block;
}

}  // namespace

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

  m_cellStress_N_m2.setZero(9, cellCount);
  m_boundScale.setZero(cellCount);
  for (CellTangents& slot : m_tangents) slot.setZero(81, cellCount);
  PartBounds bounds;
  for (int p = 0; p <= kParts; ++p) bounds[static_cast<std::size_t>(p)] = nodeCount * p / kParts;
  prepareProducts(bounds);
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
  CellTangents* const tangents =
      pass.stiffness == StiffnessSlot::None
          ? nullptr
          : &m_tangents[static_cast<std::size_t>(
                pass.stiffness == StiffnessSlot::Current ? m_current : 1 - m_current)];
  const bool needsTangent = tangents != nullptr || pass.nodeStiffness != nullptr;

  // Each cell's F_c, V0_c P_c and V0_c T_c.
  forEachNodeRange(
      m_pool, m_cells.cellCount(),
      [&](int range, Eigen::Index begin, Eigen::Index end) {
        TetFieldReport seen;
        for (Eigen::Index c = begin; c < end; ++c) {
          Eigen::Map<Eigen::Matrix3d> stress(m_cellStress_N_m2.col(c).data());
          stress.setZero();
          if (tangents != nullptr) tangents->col(c).setZero();
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
          if (tangents != nullptr) Eigen::Map<StressTangent>(tangents->col(c).data()) = tangent;
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

  // f_j = -sum over the cells c that hold j of V0_c P_c G_cj.
  forEachNodeRange(
      m_pool, x.cols(),
      [&](int, Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index j = begin; j < end; ++j) {
          const auto u = static_cast<std::size_t>(j);
          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
          double bound = 0.0;
          for (int n = m_nodeEntryStart[u]; n < m_nodeEntryStart[u + 1]; ++n) {
            const int e = m_nodeEntries[static_cast<std::size_t>(n)];
            const int c = m_entryCell[static_cast<std::size_t>(e)];
            const auto g = m_cells.gradients_1_m.col(e);
            sum += Eigen::Map<const Eigen::Matrix3d>(m_cellStress_N_m2.col(c).data()) * g;
            if (pass.nodeStiffness != nullptr) bound += m_boundScale[c] * g.norm();
          }
          f.col(j) -= sum;
          if (pass.nodeStiffness != nullptr) (*pass.nodeStiffness)[j] += bound;
        }
      },
      0);

  for (const TetFieldReport& seen : m_rangeReport) report.tets.include(seen);
}

void SmoothedStrainForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  // Each of its entries' share of its cell's gather, 9x9 product and scatter.
  for (std::size_t j = 0; j + 1 < m_nodeEntryStart.size(); ++j) {
    for (int n = m_nodeEntryStart[j]; n < m_nodeEntryStart[j + 1]; ++n) {
      const auto c = static_cast<std::size_t>(
          m_entryCell[static_cast<std::size_t>(m_nodeEntries[static_cast<std::size_t>(n)])]);
      nodeWork[j] += 18 + 81 / (m_cells.start[c + 1] - m_cells.start[c]);
    }
  }
}

void SmoothedStrainForceField::prepareProducts(const PartBounds& bounds) {
  if (bounds == m_bounds) return;
  m_bounds = bounds;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kParts); ++p) {
    std::vector<int>& cells = m_partCells[p];
    cells.clear();
    for (Eigen::Index j = bounds[p]; j < bounds[p + 1]; ++j) {
      const auto u = static_cast<std::size_t>(j);
      for (int n = m_nodeEntryStart[u]; n < m_nodeEntryStart[u + 1]; ++n) {
        cells.push_back(
            m_entryCell[static_cast<std::size_t>(m_nodeEntries[static_cast<std::size_t>(n)])]);
      }
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    m_partProjection[p].setZero(9, m_cells.cellCount());
  }
}

void SmoothedStrainForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  const CellTangents& tangents = currentTangents();
  const auto p = static_cast<std::size_t>(part);
  Eigen::Matrix<double, 9, Eigen::Dynamic>& projection = m_partProjection[p];
  // V0_c T_c : dF_c for each cell this part's nodes lie in.
  for (const int c : m_partCells[p]) {
    const auto u = static_cast<std::size_t>(c);
    RowMajor3d dF = RowMajor3d::Zero();
    for (int e = m_cells.start[u]; e < m_cells.start[u + 1]; ++e) {
      dF += Eigen::Map<const Eigen::Vector3d>(x + 3 * m_cells.nodes[static_cast<std::size_t>(e)]) *
            m_cells.gradients_1_m.col(e).transpose();
    }
    projection.col(c) = Eigen::Map<const StressTangent>(tangents.col(c).data()) *
                        Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
  }
  for (Eigen::Index j = m_bounds[p]; j < m_bounds[p + 1]; ++j) {
    const auto u = static_cast<std::size_t>(j);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int n = m_nodeEntryStart[u]; n < m_nodeEntryStart[u + 1]; ++n) {
      const int e = m_nodeEntries[static_cast<std::size_t>(n)];
      sum += Eigen::Map<const RowMajor3d>(
                 projection.col(m_entryCell[static_cast<std::size_t>(e)]).data()) *
             m_cells.gradients_1_m.col(e);
    }
    Eigen::Map<Eigen::Vector3d>(y + 3 * j) += sum;
  }
}

void SmoothedStrainForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  const CellTangents& tangents = currentTangents();
  const auto u = static_cast<std::size_t>(j);
  for (int n = m_nodeEntryStart[u]; n < m_nodeEntryStart[u + 1]; ++n) {
    const int e = m_nodeEntries[static_cast<std::size_t>(n)];
    const Eigen::Vector3d g = m_cells.gradients_1_m.col(e);
    block += contract(tangents.col(m_entryCell[static_cast<std::size_t>(e)]).data(), g, g);
  }
}

void SmoothedStrainForceField::addStiffness(NodeBlockMatrix& matrix) const {
  const CellTangents& tangents = currentTangents();
  for (std::size_t c = 0; c + 1 < m_cells.start.size(); ++c) {
    const double* tangent = tangents.col(static_cast<Eigen::Index>(c)).data();
    for (int e = m_cells.start[c]; e < m_cells.start[c + 1]; ++e) {
      for (int h = m_cells.start[c]; h < m_cells.start[c + 1]; ++h) {
        matrix.addBlock(
            m_cells.nodes[static_cast<std::size_t>(e)], m_cells.nodes[static_cast<std::size_t>(h)],
            contract(tangent, m_cells.gradients_1_m.col(e), m_cells.gradients_1_m.col(h)));
      }
    }
  }
}

}  // namespace tissuesim
