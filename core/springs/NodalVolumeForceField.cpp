// SPDX-License-Identifier: Apache-2.0
#include "springs/NodalVolumeForceField.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"
#include "springs/VolumeForceField.h"

namespace tissuesim {

NodalVolumeForceField::NodalVolumeForceField(const Eigen::Matrix3Xd& restPositions_m,
                                             const Eigen::Matrix4Xi& tets, double bulkModulus_Pa)
    : m_tets(tets), m_bulkModulus_Pa(bulkModulus_Pa) {
  if (!(bulkModulus_Pa > 0.0)) throw std::invalid_argument("the bulk modulus must be above 0");
  const Eigen::Index nodeCount = restPositions_m.cols();
  const Eigen::Index tetCount = tets.cols();

  // Each node's share of its tets' rest volume.
  Eigen::VectorXd restVolume_m3 = Eigen::VectorXd::Zero(nodeCount);
  double gradient[12];
  for (Eigen::Index t = 0; t < tetCount; ++t) {
    const double volume = signedTetVolumeGradient(restPositions_m, tets, t, gradient);
    if (!(volume > 0.0)) {
      throw std::invalid_argument("tet " + std::to_string(t) +
                                  " is not positively oriented at rest");
    }
    for (int c = 0; c < 4; ++c) restVolume_m3[tets(c, t)] += 0.25 * volume;
  }
  m_inverseNodeRestVolume_1_m3.resize(nodeCount);
  for (Eigen::Index a = 0; a < nodeCount; ++a) {
    // A node in no tet has no volume to hold: its k_a and p_a stay 0.
    m_inverseNodeRestVolume_1_m3[a] = restVolume_m3[a] > 0.0 ? 1.0 / restVolume_m3[a] : 0.0;
  }

  // Each node's tets and its star.
  m_tetsOfNode = nodeTetIncidence(tets, nodeCount);
  m_stars = nodeStars(tets, m_tetsOfNode);
  m_mirror = starMirror(m_stars);
  m_tetStarEntry.resize(16, tetCount);
  for (Eigen::Index t = 0; t < tetCount; ++t) {
    for (int c = 0; c < 4; ++c) {
      for (int n = 0; n < 4; ++n)
        m_tetStarEntry(4 * c + n, t) = starEntry(m_stars, tets(c, t), tets(n, t));
    }
  }

  m_tetVolume_m3.setZero(tetCount);
  m_gradientNorm_m2.setZero(nodeCount);
  m_tetGradient_m2.setZero(12, tetCount);
  for (Slot& slot : m_slots) {
    slot.starGradient_m2.setZero(3, static_cast<Eigen::Index>(m_stars.nodes.size()));
    slot.pressure_Pa.setZero(nodeCount);
    slot.positions_m.setZero(3, nodeCount);
  }
  PartBounds bounds;
  for (int p = 0; p <= kParts; ++p) bounds[static_cast<std::size_t>(p)] = nodeCount * p / kParts;
  prepareProducts(bounds);
}

Eigen::Matrix2Xi NodalVolumeForceField::couplings() const { return starCouplings(m_stars); }

double NodalVolumeForceField::energy(const Eigen::Matrix3Xd& x) const {
  Eigen::VectorXd volume_m3 = Eigen::VectorXd::Zero(x.cols());
  double gradient[12];
  for (Eigen::Index t = 0; t < m_tets.cols(); ++t) {
    const double v = signedTetVolumeGradient(x, m_tets, t, gradient);
    for (int c = 0; c < 4; ++c) volume_m3[m_tets(c, t)] += 0.25 * v;
  }
  double total = 0.0;
  for (Eigen::Index a = 0; a < x.cols(); ++a) {
    const double inverse = m_inverseNodeRestVolume_1_m3[a];
    if (inverse == 0.0) continue;
    const double strain = volume_m3[a] * inverse - 1.0;
    total += 0.5 * m_bulkModulus_Pa * strain * strain / inverse;
  }
  return total;
}

void NodalVolumeForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                      const ForcePass& pass, ForceReport& report) const {
  const Eigen::Index tetCount = m_tets.cols();
  runParts(m_pool, kTetRanges, [&](int part) {
    int inverted = 0;
    for (Eigen::Index t = tetCount * part / kTetRanges; t < tetCount * (part + 1) / kTetRanges;
         ++t) {
      const double v = signedTetVolumeGradient(x, m_tets, t, m_tetGradient_m2.col(t).data());
      m_tetVolume_m3[t] = v;
      if (!(v > 0.0)) ++inverted;
    }
    m_partInverted[static_cast<std::size_t>(part)] = inverted;
  });

  const int slotIndex = pass.stiffness == StiffnessSlot::Current ? m_current
                        : pass.stiffness == StiffnessSlot::Trial ? 1 - m_current
                                                                 : 2;
  Slot& slot = m_slots[static_cast<std::size_t>(slotIndex)];
  slot.isExact = pass.stiffness != StiffnessSlot::None && !pass.isProjected;
  if (slot.isExact) slot.positions_m = x;
  const double kappa = m_bulkModulus_Pa;

  // Each node's volume, pressure and g_a, in its own star's entries.
  forEachNodeRange(
      m_pool, x.cols(),
      [&](int range, Eigen::Index begin, Eigen::Index end) {
        VolumeFieldReport seen;
        for (Eigen::Index a = begin; a < end; ++a) {
          const auto u = static_cast<std::size_t>(a);
          slot.starGradient_m2.middleCols(m_stars.start[u], m_stars.start[u + 1] - m_stars.start[u])
              .setZero();
          double volume = 0.0;
          for (int e = m_tetsOfNode.start[u]; e < m_tetsOfNode.start[u + 1]; ++e) {
            const int t = m_tetsOfNode.entries[static_cast<std::size_t>(e)] / 4;
            const int c = m_tetsOfNode.entries[static_cast<std::size_t>(e)] % 4;
            volume += 0.25 * m_tetVolume_m3[t];
            for (int n = 0; n < 4; ++n) {
              slot.starGradient_m2.col(m_tetStarEntry(4 * c + n, t)) +=
                  0.25 * m_tetGradient_m2.block<3, 1>(3 * n, t);
            }
          }
          if (pass.nodeStiffness != nullptr) {
            m_gradientNorm_m2[a] =
                slot.starGradient_m2
                    .middleCols(m_stars.start[u], m_stars.start[u + 1] - m_stars.start[u])
                    .norm();
          }
          const double inverse = m_inverseNodeRestVolume_1_m3[a];
          if (inverse == 0.0) {
            slot.pressure_Pa[a] = 0.0;
            continue;
          }
          const double ratio = volume * inverse;
          seen.minVolumeRatio = std::min(seen.minVolumeRatio, ratio);
          seen.maxVolumeRatio = std::max(seen.maxVolumeRatio, ratio);
          slot.pressure_Pa[a] = kappa * (ratio - 1.0);
        }
        m_rangeReport[static_cast<std::size_t>(range)] = seen;
      },
      0);

  // f_j = -sum over the stars j lies in of p_a g_a[j]; the bound sums k_a |g_a[j]| |g_a|.
  forEachNodeRange(
      m_pool, x.cols(),
      [&](int, Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index j = begin; j < end; ++j) {
          const auto u = static_cast<std::size_t>(j);
          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
          double bound = 0.0;
          for (int e = m_stars.start[u]; e < m_stars.start[u + 1]; ++e) {
            const int a = m_stars.nodes[static_cast<std::size_t>(e)];
            const auto g = slot.starGradient_m2.col(m_mirror[static_cast<std::size_t>(e)]);
            sum += slot.pressure_Pa[a] * g;
            if (pass.nodeStiffness != nullptr)
              bound += kappa * m_inverseNodeRestVolume_1_m3[a] * g.norm() * m_gradientNorm_m2[a];
          }
          f.col(j) -= sum;
          if (pass.nodeStiffness != nullptr) (*pass.nodeStiffness)[j] += bound;
        }
      },
      0);

  for (const VolumeFieldReport& seen : m_rangeReport) report.volume.include(seen);
  for (const int inverted : m_partInverted) report.volume.invertedTetCount += inverted;
}

void NodalVolumeForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  for (std::size_t j = 0; j + 1 < m_stars.start.size(); ++j) {
    nodeWork[j] += 12 * (m_stars.start[j + 1] - m_stars.start[j]);
  }
}

void NodalVolumeForceField::prepareProducts(const PartBounds& bounds) {
  if (bounds == m_bounds) return;
  m_bounds = bounds;
  const auto nodeCount = static_cast<Eigen::Index>(m_stars.start.size()) - 1;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kParts); ++p) {
    std::vector<int>& centres = m_partStars[p];
    centres.clear();
    for (Eigen::Index j = bounds[p]; j < bounds[p + 1]; ++j) {
      const auto u = static_cast<std::size_t>(j);
      centres.insert(centres.end(), m_stars.nodes.begin() + m_stars.start[u],
                     m_stars.nodes.begin() + m_stars.start[u + 1]);
    }
    std::sort(centres.begin(), centres.end());
    centres.erase(std::unique(centres.begin(), centres.end()), centres.end());
    m_partProjection[p].setZero(nodeCount);
  }
}

void NodalVolumeForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  const Slot& slot = currentSlot();
  const auto p = static_cast<std::size_t>(part);
  Eigen::VectorXd& projection = m_partProjection[p];
  // s_a = k_a g_a . x for each star this part's nodes lie in.
  for (const int a : m_partStars[p]) {
    const auto u = static_cast<std::size_t>(a);
    double dot = 0.0;
    for (int e = m_stars.start[u]; e < m_stars.start[u + 1]; ++e) {
      dot += slot.starGradient_m2.col(e).dot(
          Eigen::Map<const Eigen::Vector3d>(x + 3 * m_stars.nodes[static_cast<std::size_t>(e)]));
    }
    projection[a] = m_bulkModulus_Pa * m_inverseNodeRestVolume_1_m3[a] * dot;
  }
  for (Eigen::Index j = m_bounds[p]; j < m_bounds[p + 1]; ++j) {
    const auto u = static_cast<std::size_t>(j);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int e = m_stars.start[u]; e < m_stars.start[u + 1]; ++e) {
      sum += projection[m_stars.nodes[static_cast<std::size_t>(e)]] *
             slot.starGradient_m2.col(m_mirror[static_cast<std::size_t>(e)]);
    }
    Eigen::Map<Eigen::Vector3d>(y + 3 * j) += sum;
  }
}

void NodalVolumeForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  const Slot& slot = currentSlot();
  const auto u = static_cast<std::size_t>(j);
  for (int e = m_stars.start[u]; e < m_stars.start[u + 1]; ++e) {
    const int a = m_stars.nodes[static_cast<std::size_t>(e)];
    const Eigen::Vector3d g = slot.starGradient_m2.col(m_mirror[static_cast<std::size_t>(e)]);
    block += (m_bulkModulus_Pa * m_inverseNodeRestVolume_1_m3[a]) * g * g.transpose();
  }
}

void NodalVolumeForceField::addStiffness(NodeBlockMatrix& matrix) const {
  const Slot& slot = currentSlot();
  for (std::size_t a = 0; a + 1 < m_stars.start.size(); ++a) {
    const double k = m_bulkModulus_Pa * m_inverseNodeRestVolume_1_m3[static_cast<Eigen::Index>(a)];
    if (k == 0.0) continue;
    for (int e = m_stars.start[a]; e < m_stars.start[a + 1]; ++e) {
      for (int f = m_stars.start[a]; f < m_stars.start[a + 1]; ++f) {
        matrix.addBlock(m_stars.nodes[static_cast<std::size_t>(e)],
                        m_stars.nodes[static_cast<std::size_t>(f)],
                        k * slot.starGradient_m2.col(e) * slot.starGradient_m2.col(f).transpose());
      }
    }
  }
  if (!slot.isExact) return;
  // The exact Hessian's other part: sum_a p_a d2V_a/dx2 = sum_t pbar_t d2V_t/dx2.
  for (Eigen::Index t = 0; t < m_tets.cols(); ++t) {
    double pressure = 0.0;
    for (int c = 0; c < 4; ++c) pressure += 0.25 * slot.pressure_Pa[m_tets(c, t)];
    const std::array<Eigen::Matrix3d, 16> h = tetVolumeHessian(slot.positions_m, m_tets.col(t));
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        matrix.addBlock(m_tets(i, t), m_tets(j, t),
                        pressure * h[static_cast<std::size_t>(4 * i + j)]);
      }
    }
  }
}

}  // namespace tissuesim
