// SPDX-License-Identifier: Apache-2.0
#include "fem/TetIsochoricForceField.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <Eigen/LU>

#include "fem/IsochoricMaterialPoint.h"
#include "mesh/TetMesh.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

using Matrix9d = StressTangent;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

TetIsochoricForceField::TetIsochoricForceField(const Eigen::Matrix3Xd& restPositions_m,
                                               const Eigen::Matrix4Xi& tets,
                                               const StrainEnergy& energy)
    : m_tets(tets), m_energy(energy), m_limitShift(energy.usableInvariantShift()) {
  const Eigen::Index tetCount = tets.cols();
  const Eigen::Index nodeCount = restPositions_m.cols();
  m_gradients.resize(12, tetCount);
  m_restVolume_m3.resize(tetCount);
  for (Eigen::Index t = 0; t < tetCount; ++t) {
    Eigen::Matrix3d dm;
    for (int a = 1; a < 4; ++a) {
      dm.col(a - 1) = restPositions_m.col(tets(a, t)) - restPositions_m.col(tets(0, t));
    }
    const double volume = dm.determinant() / 6.0;
    if (!(volume > 0.0)) {
      throw std::invalid_argument("tet " + std::to_string(t) +
                                  " is not positively oriented at rest");
    }
    m_restVolume_m3[t] = volume;
    const Eigen::Matrix3d inverse = dm.inverse();
    // F = Ds Dm^-1 = sum_a x_a g_a^T: g_1..g_3 are Dm^-1's rows, g_0 minus their sum.
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int a = 1; a < 4; ++a) {
      m_gradients.block<3, 1>(3 * a, t) = inverse.row(a - 1).transpose();
      sum += inverse.row(a - 1).transpose();
    }
    m_gradients.block<3, 1>(0, t) = -sum;
  }
  // Each node's tets, its neighbours through them (its row of K), and where each incidence's
  // four blocks go.
  m_tetsOfNode = nodeTetIncidence(tets, nodeCount);
  m_rows = NodeRowStiffness(nodeStars(tets, m_tetsOfNode));
  m_incidenceSlot.resize(4 * m_tetsOfNode.entries.size());
  for (Eigen::Index j = 0; j < nodeCount; ++j) {
    const auto u = static_cast<std::size_t>(j);
    for (int e = m_tetsOfNode.start[u]; e < m_tetsOfNode.start[u + 1]; ++e) {
      const int t = m_tetsOfNode.entries[static_cast<std::size_t>(e)] / 4;
      for (int n = 0; n < 4; ++n) {
        m_incidenceSlot[4 * static_cast<std::size_t>(e) + static_cast<std::size_t>(n)] =
            m_rows.entry(static_cast<int>(j), tets(n, t));
      }
    }
  }
  m_tetForces_N.setZero(12, tetCount);
  m_tetStiffness.setZero(144, tetCount);
  for (Eigen::Index p = 0; p <= kParts; ++p) {
    m_bounds[static_cast<std::size_t>(p)] = nodeCount * p / kParts;
  }
}

double TetIsochoricForceField::energy(const Eigen::Matrix3Xd& x) const {
  double total = 0.0;
  for (Eigen::Index t = 0; t < m_tets.cols(); ++t) {
    Eigen::Matrix3d f = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a) {
      f += x.col(m_tets(a, t)) * m_gradients.block<3, 1>(3 * a, t).transpose();
    }
    const double j = f.determinant();
    if (!(j > 0.0)) continue;
    const double shift = std::pow(j, -2.0 / 3.0) * f.squaredNorm() - 3.0;
    total +=
        m_restVolume_m3[t] * continuedIsochoricEnergy(m_energy, shift, m_limitShift, true).energy;
  }
  return total;
}

void TetIsochoricForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                       const ForcePass& pass, ForceReport& report) const {
  const bool needsStiffness =
      pass.stiffness != StiffnessSlot::None || pass.nodeStiffness != nullptr;
  TetStiffness& k = m_tetStiffness;
  const Eigen::Index tetCount = m_tets.cols();
  const auto tetRange = [&](int part) {
    const Eigen::Index begin = tetCount * part / kTetRanges;
    const Eigen::Index end = tetCount * (part + 1) / kTetRanges;
    int beyondRange = 0;
    int inverted = 0;
    for (Eigen::Index t = begin; t < end; ++t) {
      Eigen::Matrix3d deformation = Eigen::Matrix3d::Zero();
      for (int a = 0; a < 4; ++a) {
        deformation += x.col(m_tets(a, t)) * m_gradients.block<3, 1>(3 * a, t).transpose();
      }
      const double j = deformation.determinant();
      if (!(j > 0.0)) {
        ++inverted;
        m_tetForces_N.col(t).setZero();
        if (needsStiffness) k.col(t).setZero();
        continue;
      }
      const double i1 = deformation.squaredNorm();
      const double scale = std::pow(j, -2.0 / 3.0);  // J^(-2/3)
      const double shift = scale * i1 - 3.0;
      if (shift > m_limitShift) ++beyondRange;
      const EnergyInI1 w = continuedIsochoricEnergy(m_energy, shift, m_limitShift, false);
      const Eigen::Matrix3d inverseTranspose = deformation.inverse().transpose();
      // A = dI1bar/dF; P = W_T' A.
      const Eigen::Matrix3d a = scale * (2.0 * deformation - (2.0 / 3.0) * i1 * inverseTranspose);
      const Eigen::Matrix3d stress = w.dEnergy * a;
      const double volume = m_restVolume_m3[t];
      for (int n = 0; n < 4; ++n) {
        m_tetForces_N.block<3, 1>(3 * n, t) = -volume * stress * m_gradients.block<3, 1>(3 * n, t);
      }
      if (!needsStiffness) continue;
      const Matrix9d tangent = pass.isProjected
                                   ? projectedIsochoricTangent(deformation, w.dEnergy, w.d2Energy)
                                   : exactIsochoricTangent(deformation, a, i1, scale, w);
      // K_(a i)(b k) = V0 sum_JL T_(iJ)(kL) g_aJ g_bL, as (T B) then B^T (T B), B's sparsity
      // used (dF_iJ / dx_(b k) = delta_ik g_bJ).
      Eigen::Matrix<double, 9, 12> tb;
      for (int n = 0; n < 4; ++n) {
        const Eigen::Vector3d gn = m_gradients.block<3, 1>(3 * n, t);
        for (int kk = 0; kk < 3; ++kk) {
          tb.col(3 * n + kk) = tangent.col(3 * kk) * gn(0) + tangent.col(3 * kk + 1) * gn(1) +
                               tangent.col(3 * kk + 2) * gn(2);
        }
      }
      Eigen::Map<Matrix12d> kt(k.col(t).data());
      for (int n = 0; n < 4; ++n) {
        const Eigen::Vector3d gn = volume * m_gradients.block<3, 1>(3 * n, t);
        for (int ii = 0; ii < 3; ++ii) {
          kt.row(3 * n + ii) =
              gn(0) * tb.row(3 * ii) + gn(1) * tb.row(3 * ii + 1) + gn(2) * tb.row(3 * ii + 2);
        }
      }
    }
    m_partBeyondRange[static_cast<std::size_t>(part)] = beyondRange;
    m_partInverted[static_cast<std::size_t>(part)] = inverted;
  };
  runParts(m_pool, kTetRanges, tetRange);
  NodeRowStiffness::Blocks* const rowBlocks =
      pass.stiffness == StiffnessSlot::None ? nullptr : &m_rows.slot(pass.stiffness);
  const auto gather = [&](int, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      const auto u = static_cast<std::size_t>(j);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      double bound = 0.0;
      if (rowBlocks != nullptr) m_rows.clearRow(*rowBlocks, j);
      for (int e = m_tetsOfNode.start[u]; e < m_tetsOfNode.start[u + 1]; ++e) {
        const int t = m_tetsOfNode.entries[static_cast<std::size_t>(e)] / 4;
        const int a = m_tetsOfNode.entries[static_cast<std::size_t>(e)] % 4;
        sum += m_tetForces_N.block<3, 1>(3 * a, t);
        const Eigen::Map<const Matrix12d> kt(k.col(t).data());
        if (pass.nodeStiffness != nullptr) bound += kt.norm();
        if (rowBlocks == nullptr) continue;
        for (int n = 0; n < 4; ++n) {
          const int slot =
              m_incidenceSlot[4 * static_cast<std::size_t>(e) + static_cast<std::size_t>(n)];
          Eigen::Map<Eigen::Matrix3d>(rowBlocks->col(slot).data()) += kt.block<3, 3>(3 * a, 3 * n);
        }
      }
      f.col(j) += sum;
      if (pass.nodeStiffness != nullptr) (*pass.nodeStiffness)[j] += bound;
    }
  };
  forEachNodeRange(m_pool, x.cols(), gather);
  for (int part = 0; part < kTetRanges; ++part) {
    report.tets.beyondRangeCount += m_partBeyondRange[static_cast<std::size_t>(part)];
    report.tets.invertedCount += m_partInverted[static_cast<std::size_t>(part)];
  }
}

void TetIsochoricForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  m_rows.addProductWork(nodeWork);
}

void TetIsochoricForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  const auto p = static_cast<std::size_t>(part);
  m_rows.addProduct(m_bounds[p], m_bounds[p + 1], x, y);
}

void TetIsochoricForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  m_rows.addDiagonalBlock(j, block);
}

void TetIsochoricForceField::addStiffness(NodeBlockMatrix& matrix) const {
  m_rows.addStiffness(matrix);
}

}  // namespace tissuesim
