// SPDX-License-Identifier: Apache-2.0
#include "fem/FemModel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

#include <Eigen/LU>

#include "fem/IsochoricMaterialPoint.h"
#include "fem/QuadraticTetShape.h"

namespace tissuesim {

double defaultFemBulkModulus(const StrainEnergy& energy) {
  // The uniaxial tangent dP/dlambda rises monotonically with the stretch: its value at the top
  // of the range is the stiffest the tissue gets there.
  const double top = std::min(kFemBulkModulusStretch, energy.usableRange().upper);
  const double stiffest =
      std::max(3.0 * energy.initialShearModulus(), energy.stressAndSlope(top).slope);
  return kFemBulkModulusFactor * stiffest;
}

FemModel::FemModel(const QuadraticTetMesh& mesh, const StrainEnergy& energy, double bulkModulus_Pa)
    : m_mesh(mesh),
      m_energy(energy),
      m_bulkModulus_Pa(bulkModulus_Pa),
      m_restVolume_m3(mesh.tetCount()) {
  if (!(bulkModulus_Pa > 0.0) || !std::isfinite(bulkModulus_Pa))
    throw std::invalid_argument("the FEM's bulk modulus must be positive and finite");
  const auto energyRule = tetQuadratureDegree2();
  const auto volumeRule = tetQuadratureDegree3();
  m_energyPoints.reserve(4 * static_cast<std::size_t>(mesh.tetCount()));
  m_volumePoints.reserve(5 * static_cast<std::size_t>(mesh.tetCount()));
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    // dX/dxi at each point: constant on a straight-edged tet, linear in xi on one with a curved
    // boundary edge (isoparametric: QuadraticTetShape.h).
    const auto restPoint = [&](const TetQuadraturePoint& point) -> PointData {
      const Eigen::Matrix3d jacobian = quadraticTetJacobian(mesh, t, point.xi);
      const double determinant = jacobian.determinant();
      if (!(determinant > 0.0)) {
        throw std::invalid_argument("FEM: element " + std::to_string(t) +
                                    " is flat or inverted at rest");
      }
      return {quadraticTetShapeGradients(point.xi) * jacobian.inverse(),
              point.weight * determinant};
    };
    for (const TetQuadraturePoint& point : energyRule) m_energyPoints.push_back(restPoint(point));
    // V_e by the rule its deformed volume takes (exact: det(dX/dxi) is cubic in xi).
    double restVolume_m3 = 0.0;
    for (const TetQuadraturePoint& point : volumeRule) {
      m_volumePoints.push_back(restPoint(point));
      restVolume_m3 += m_volumePoints.back().weight_m3;
    }
    if (!(restVolume_m3 > 0.0))
      throw std::invalid_argument("FEM: element " + std::to_string(t) + " has no volume at rest");
    m_restVolume_m3[t] = restVolume_m3;
  }
  // Two halves for two threads (setElementThreads): the elements wholly below and wholly above
  // the nodes' median along the rest mesh's longest side; a cut one element thick between them.
  if (mesh.tetCount() < kElementsForTwoThreads) return;
  Eigen::Index axis = 0;
  (mesh.nodes_m.rowwise().maxCoeff() - mesh.nodes_m.rowwise().minCoeff()).maxCoeff(&axis);
  std::vector<double> along(static_cast<std::size_t>(mesh.nodes_m.cols()));
  for (Eigen::Index v = 0; v < mesh.nodes_m.cols(); ++v)
    along[static_cast<std::size_t>(v)] = mesh.nodes_m(axis, v);
  const auto middle = along.begin() + static_cast<std::ptrdiff_t>(along.size() / 2);
  std::nth_element(along.begin(), middle, along.end());
  const double median = *middle;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    int below = 0;
    for (int a = 0; a < 10; ++a) below += mesh.nodes_m(axis, mesh.tets(a, t)) < median ? 1 : 0;
    (below == 10 ? m_lowerElements : below == 0 ? m_upperElements : m_elementsAcross).push_back(t);
  }
  setElementThreads(2);
}

void FemModel::setElementThreads(int threads) {
  if (threads != 1 && threads != 2)
    throw std::invalid_argument("FemModel: an evaluation's elements go on 1 or 2 threads");
  m_pool.reset();
  if (threads == 1 || m_lowerElements.empty() || m_upperElements.empty()) return;
  try {
    m_pool = std::make_unique<ForkJoinPool>(2);
  } catch (const std::system_error&) {  // no thread to be had: the caller's alone
  }
}

FemState FemModel::evaluate(const Eigen::Matrix3Xd& x) const {
  return accumulate(x, nullptr, nullptr, nullptr);
}

FemState FemModel::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& gradient) const {
  gradient.setZero(3, x.cols());
  return accumulate(x, &gradient, nullptr, nullptr);
}

FemState FemModel::evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& gradient,
                            Eigen::SparseMatrix<double>& hessian, const std::vector<char>& isFixed,
                            FemHessianAssembly* assembly) const {
  gradient.setZero(3, x.cols());
  const Eigen::Index dofs = 3 * x.cols();
  const bool isKnown =
      assembly != nullptr && assembly->isFixed == isFixed && !assembly->slots.empty() &&
      assembly->firstEntries.size() == static_cast<std::size_t>(m_mesh.tetCount()) &&
      hessian.rows() == dofs && hessian.cols() == dofs && hessian.isCompressed();
  if (isKnown) {
    // The same elements and fixed DOFs as the pattern's: their entries added straight into its
    // values, the fixed diagonal's ones, and the extra energy's few entries looked up (inserted
    // where new).
    Eigen::Map<Eigen::VectorXd> values(hessian.valuePtr(), hessian.nonZeros());
    values.setZero();
    std::vector<Eigen::Triplet<double>> extra;
    const FemState state =
        accumulate(x, &gradient, &extra, &isFixed, nullptr,
                   {hessian.valuePtr(), assembly->slots.data(), assembly->firstEntries.data()});
    for (Eigen::Index d = 0; d < dofs; ++d) {
      if (!isFixed.empty() && isFixed[static_cast<std::size_t>(d)] != 0) hessian.coeffRef(d, d) = 1;
    }
    for (const Eigen::Triplet<double>& entry : extra)
      hessian.coeffRef(entry.row(), entry.col()) += entry.value();
    if (!hessian.isCompressed()) {  // an entry was inserted: the slots are stale
      hessian.makeCompressed();
      assembly->slots.clear();
    }
    return state;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(900 * static_cast<std::size_t>(m_mesh.tetCount()));
  std::size_t elementEntries = 0;
  std::vector<std::size_t> firstEntries;
  const FemState state =
      accumulate(x, &gradient, &triplets, &isFixed, &elementEntries, {nullptr, nullptr, nullptr},
                 assembly != nullptr ? &firstEntries : nullptr);
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (!isFixed.empty() && isFixed[static_cast<std::size_t>(d)] != 0)
      triplets.emplace_back(d, d, 1.0);
  }
  hessian.resize(dofs, dofs);
  hessian.setFromTriplets(triplets.begin(), triplets.end());
  if (assembly != nullptr) {
    assembly->isFixed = isFixed;
    assembly->slots.resize(elementEntries);
    for (std::size_t e = 0; e < elementEntries; ++e) {
      const Eigen::Index column = triplets[e].col();
      const int* begin = hessian.innerIndexPtr() + hessian.outerIndexPtr()[column];
      const int* end = hessian.innerIndexPtr() + hessian.outerIndexPtr()[column + 1];
      assembly->slots[e] =
          std::lower_bound(begin, end, triplets[e].row()) - hessian.innerIndexPtr();
    }
    assembly->firstEntries = std::move(firstEntries);
  }
  return state;
}

namespace {

using ElementMatrix = Eigen::Matrix<double, 30, 30>;
using ElementVector = Eigen::Matrix<double, 30, 1>;

/// F = sum_a x_a (dN_a/dX)^T of element nodes `xe` (3 by 10).
Eigen::Matrix3d deformationGradient(const Eigen::Matrix<double, 3, 10>& xe,
                                    const Eigen::Matrix<double, 10, 3>& gradients) {
  return xe * gradients;
}

}  // namespace

bool FemModel::addElement(Eigen::Index t, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                          std::vector<Eigen::Triplet<double>>* triplets,
                          const std::vector<char>* isFixed, DirectAssembly direct,
                          FemState& state) const {
  const bool withGradient = gradient != nullptr;
  const bool withHessian = triplets != nullptr || direct.values != nullptr;
  // Its entries from its first on, in the order the slots were made in.
  std::size_t entry = direct.values != nullptr ? direct.firstEntries[t] : 0;
  ElementVector ge;
  ElementMatrix he;
  ElementMatrix isochoric;  // the isochoric part of he, rows and columns ordered 10 i + a
  const bool isSoftened = m_softening != nullptr && !m_peaks.empty();
  Eigen::Matrix<double, 3, 10> xe;
  for (int a = 0; a < 10; ++a) xe.col(a) = x.col(m_mesh.tets(a, t));
  ge.setZero();
  if (withHessian) isochoric.setZero();
  // Isochoric part, four points.
  for (int q = 0; q < 4; ++q) {
    const PointData& point = m_energyPoints[static_cast<std::size_t>(4 * t + q)];
    const Eigen::Matrix3d f = deformationGradient(xe, point.gradients);
    const double j = f.determinant();
    const double shift = j > 0.0 ? isochoricShift(f) : 0.0;
    if (!(j > 0.0) || !(shift < m_energy.usableInvariantShift())) return false;
    EnergyInI1 w = m_energy.atInvariantShift(std::max(shift, 0.0));
    if (isSoftened) {  // below its peak, the point's softened energy (fem/IsochoricSoftening.h)
      w = softenedIsochoricEnergy(m_energy, *m_softening, std::max(shift, 0.0),
                                  m_peaks[static_cast<std::size_t>(4 * t + q)], w);
    }
    const bool isDefinite = m_tangent == FemTangent::Definite;
    IsochoricResponse response = evaluateIsochoric(f, w, withHessian && !isDefinite);
    if (withHessian && isDefinite)
      response.tangent_Pa = projectedIsochoricTangent(f, w.dEnergy, w.d2Energy);
    state.energy_J += point.weight_m3 * response.energy_Pa;
    if (!withGradient) continue;
    for (int a = 0; a < 10; ++a) {
      ge.segment<3>(3 * a) +=
          point.weight_m3 * response.stress_Pa * point.gradients.row(a).transpose();
    }
    if (!withHessian) continue;
    // H_ab(i, k) = sum_JL dN_a/dX_J T(iJ, kL) dN_b/dX_L: for each (i, k) the 10 by 10 block
    // G T_ik G^T of all node pairs (G = dN/dX, T_ik = T's 3 by 3 block), gathered in the
    // component-major order of isochoric; T's major symmetry makes block (k, i) block (i, k)'s
    // transpose, filled once the points are summed.
    for (int i = 0; i < 3; ++i) {
      for (int k = i; k < 3; ++k) {
        const Eigen::Matrix<double, 10, 3> left =
            point.gradients * response.tangent_Pa.block<3, 3>(3 * i, 3 * k);
        isochoric.block<10, 10>(10 * i, 10 * k).noalias() +=
            point.weight_m3 * left.lazyProduct(point.gradients.transpose());
      }
    }
  }
  if (withHessian) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        const bool isMirrored = k < i;
        for (int a = 0; a < 10; ++a) {
          for (int b = 0; b < 10; ++b) {
            he(3 * a + i, 3 * b + k) =
                isMirrored ? isochoric(10 * k + b, 10 * i + a) : isochoric(10 * i + a, 10 * k + b);
          }
        }
      }
    }
  }
  // Volumetric part: theta = v / V, v by the degree-3 rule.
  double deformedVolume = 0.0;
  ElementVector dv = ElementVector::Zero();
  std::array<Eigen::Matrix3d, 5> fs;
  for (int q = 0; q < 5; ++q) {
    const PointData& point = m_volumePoints[static_cast<std::size_t>(5 * t + q)];
    fs[static_cast<std::size_t>(q)] = deformationGradient(xe, point.gradients);
    const Eigen::Matrix3d& f = fs[static_cast<std::size_t>(q)];
    deformedVolume += point.weight_m3 * f.determinant();
    if (!withGradient) continue;
    // dJ/dF = cof F: cof F dN_a/dX, the columns' cross products.
    Eigen::Matrix3d cofactor;
    cofactor.col(0) = f.col(1).cross(f.col(2));
    cofactor.col(1) = f.col(2).cross(f.col(0));
    cofactor.col(2) = f.col(0).cross(f.col(1));
    for (int a = 0; a < 10; ++a)
      dv.segment<3>(3 * a) += point.weight_m3 * cofactor * point.gradients.row(a).transpose();
  }
  const double restVolume = m_restVolume_m3[t];
  const double theta = deformedVolume / restVolume;
  state.minVolumeRatio = std::min(state.minVolumeRatio, theta);
  state.maxVolumeRatio = std::max(state.maxVolumeRatio, theta);
  if (!(theta > 0.0)) return false;
  const double pressure = m_bulkModulus_Pa * (theta - 1.0);  // U'(theta)
  state.energy_J += restVolume * 0.5 * m_bulkModulus_Pa * (theta - 1.0) * (theta - 1.0);
  if (withGradient) ge += pressure * dv;
  if (withHessian) {
    he += (m_bulkModulus_Pa / restVolume) * dv * dv.transpose();
    // U' d^2v/dx_a dx_b: (i, k) = sum_m eps_ikm (F (dN_a x dN_b))_m, summed over the points;
    // indefinite under compression, so the definite tangent leaves it out.
    for (int q = 0; q < 5 && m_tangent == FemTangent::Exact; ++q) {
      const PointData& point = m_volumePoints[static_cast<std::size_t>(5 * t + q)];
      const Eigen::Matrix3d& f = fs[static_cast<std::size_t>(q)];
      for (int a = 0; a < 10; ++a) {
        for (int b = 0; b < 10; ++b) {
          const Eigen::Vector3d s =
              f * point.gradients.row(a).transpose().cross(point.gradients.row(b).transpose());
          const double c = pressure * point.weight_m3;
          // eps_ikm s_m: (0,1) = s_2, (0,2) = -s_1, (1,2) = s_0, antisymmetric.
          he(3 * a + 0, 3 * b + 1) += c * s[2];
          he(3 * a + 1, 3 * b + 0) -= c * s[2];
          he(3 * a + 0, 3 * b + 2) -= c * s[1];
          he(3 * a + 2, 3 * b + 0) += c * s[1];
          he(3 * a + 1, 3 * b + 2) += c * s[0];
          he(3 * a + 2, 3 * b + 1) -= c * s[0];
        }
      }
    }
  }
  if (withGradient) {
    for (int a = 0; a < 10; ++a) gradient->col(m_mesh.tets(a, t)) += ge.segment<3>(3 * a);
  }
  if (withHessian) {
    for (int a = 0; a < 10; ++a) {
      for (int i = 0; i < 3; ++i) {
        const Eigen::Index row = 3 * m_mesh.tets(a, t) + i;
        if (!isFixed->empty() && (*isFixed)[static_cast<std::size_t>(row)] != 0) continue;
        for (int b = 0; b < 10; ++b) {
          for (int k = 0; k < 3; ++k) {
            const Eigen::Index column = 3 * m_mesh.tets(b, t) + k;
            if (!isFixed->empty() && (*isFixed)[static_cast<std::size_t>(column)] != 0) continue;
            if (direct.values != nullptr)
              direct.values[direct.slots[entry++]] += he(3 * a + i, 3 * b + k);
            else
              triplets->emplace_back(row, column, he(3 * a + i, 3 * b + k));
          }
        }
      }
    }
  }
  return true;
}

FemState FemModel::addElements(const std::vector<Eigen::Index>& elements, const Eigen::Matrix3Xd& x,
                               Eigen::Matrix3Xd* gradient, const std::vector<char>* isFixed,
                               DirectAssembly direct) const {
  FemState state;
  state.minVolumeRatio = std::numeric_limits<double>::infinity();
  state.maxVolumeRatio = -std::numeric_limits<double>::infinity();
  for (const Eigen::Index t : elements) {
    if (!addElement(t, x, gradient, nullptr, isFixed, direct, state)) {
      state.isAdmissible = false;
      state.energy_J = std::numeric_limits<double>::infinity();
      return state;
    }
  }
  return state;
}

FemState FemModel::accumulate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                              std::vector<Eigen::Triplet<double>>* triplets,
                              const std::vector<char>* isFixed, std::size_t* elementEntries,
                              DirectAssembly direct, std::vector<std::size_t>* firstEntries) const {
  FemState state;
  state.minVolumeRatio = std::numeric_limits<double>::infinity();
  state.maxVolumeRatio = -std::numeric_limits<double>::infinity();
  // Triplets made anew go in the elements' order (the slots are made from it): on one thread.
  const bool isInTwo = m_pool != nullptr && (triplets == nullptr || direct.values != nullptr);
  if (isInTwo) {
    // The halves share no node, so neither writes a gradient column or a Hessian entry the
    // other does; the elements across the cut after both. Summed in that order whatever thread
    // ran which half: the same bits each time.
    std::array<FemState, 2> halves;
    m_pool->run(2, [&](int part) {
      halves[static_cast<std::size_t>(part)] =
          addElements(part == 0 ? m_lowerElements : m_upperElements, x, gradient, isFixed, direct);
    });
    const FemState& lower = halves[0];
    const FemState& upper = halves[1];
    const FemState across = addElements(m_elementsAcross, x, gradient, isFixed, direct);
    for (const FemState* part : std::array<const FemState*, 3>{&lower, &upper, &across}) {
      if (!part->isAdmissible) {
        state.isAdmissible = false;
        state.energy_J = std::numeric_limits<double>::infinity();
        return state;
      }
      state.energy_J += part->energy_J;
      state.minVolumeRatio = std::min(state.minVolumeRatio, part->minVolumeRatio);
      state.maxVolumeRatio = std::max(state.maxVolumeRatio, part->maxVolumeRatio);
    }
  } else {
    if (firstEntries != nullptr) firstEntries->resize(static_cast<std::size_t>(m_mesh.tetCount()));
    for (Eigen::Index t = 0; t < m_mesh.tetCount(); ++t) {
      if (firstEntries != nullptr && triplets != nullptr)
        (*firstEntries)[static_cast<std::size_t>(t)] = triplets->size();
      if (!addElement(t, x, gradient, direct.values != nullptr ? nullptr : triplets, isFixed,
                      direct, state)) {
        state.isAdmissible = false;
        state.energy_J = std::numeric_limits<double>::infinity();
        return state;
      }
    }
  }
  if (elementEntries != nullptr && triplets != nullptr) *elementEntries = triplets->size();
  if (m_extra != nullptr) {
    // Its entries on fixed rows and columns are left out, as the elements' are above.
    std::vector<Eigen::Triplet<double>> extra;
    state.energy_J += m_extra->add(x, gradient, triplets != nullptr ? &extra : nullptr);
    for (const Eigen::Triplet<double>& entry : extra) {
      const bool isOnFixed =
          !isFixed->empty() && ((*isFixed)[static_cast<std::size_t>(entry.row())] != 0 ||
                                (*isFixed)[static_cast<std::size_t>(entry.col())] != 0);
      if (!isOnFixed) triplets->push_back(entry);
    }
  }
  return state;
}

void FemModel::softenAt(const Eigen::Matrix3Xd& x) {
  if (m_softening == nullptr) return;
  const std::size_t points = m_energyPoints.size();
  if (m_peaks.size() != points) m_peaks.assign(points, IsochoricPeak{});
  for (Eigen::Index t = 0; t < m_mesh.tetCount(); ++t) {
    Eigen::Matrix<double, 3, 10> xe;
    for (int a = 0; a < 10; ++a) xe.col(a) = x.col(m_mesh.tets(a, t));
    for (int q = 0; q < 4; ++q) {
      const std::size_t at = static_cast<std::size_t>(4 * t + q);
      const Eigen::Matrix3d f = deformationGradient(xe, m_energyPoints[at].gradients);
      if (!(f.determinant() > 0.0)) continue;
      const double shift = isochoricShift(f);
      if (shift > m_peaks[at].shift) m_peaks[at] = isochoricPeak(m_energy, *m_softening, shift);
    }
  }
}

void FemModel::clearSoftening() { m_peaks.clear(); }

std::vector<double> FemModel::peakShifts() const {
  std::vector<double> shifts(m_energyPoints.size(), 0.0);
  for (std::size_t p = 0; p < m_peaks.size(); ++p) shifts[p] = m_peaks[p].shift;
  return shifts;
}

Eigen::Matrix3Xd FemModel::energyPointsAtRest() const {
  const auto rule = tetQuadratureDegree2();
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(rule.size()) * m_mesh.tetCount());
  Eigen::Index at = 0;
  for (Eigen::Index t = 0; t < m_mesh.tetCount(); ++t) {
    for (const TetQuadraturePoint& point : rule) {
      const Eigen::Vector4d l(1.0 - point.xi.sum(), point.xi.x(), point.xi.y(), point.xi.z());
      const Eigen::Matrix<double, 10, 1> shape = quadraticTetShapeValues(l);
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int a = 0; a < 10; ++a) x += shape(a) * m_mesh.nodes_m.col(m_mesh.tets(a, t));
      points.col(at++) = x;
    }
  }
  return points;
}

void FemModel::setPeakShifts(const std::vector<double>& shifts) {
  if (shifts.size() != m_energyPoints.size())
    throw std::invalid_argument("FemModel: one peak a quadrature point");
  m_peaks.assign(shifts.size(), IsochoricPeak{});
  if (m_softening == nullptr) return;
  for (std::size_t p = 0; p < shifts.size(); ++p) {
    if (shifts[p] > 0.0) m_peaks[p] = isochoricPeak(m_energy, *m_softening, shifts[p]);
  }
}

}  // namespace tissuesim
