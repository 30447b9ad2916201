// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeForceField.h"

#include <algorithm>
#include <array>

#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"
#include "numerics/SymmetricBlock.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

std::array<Eigen::Matrix3d, 16> tetVolumeHessian(const Eigen::Matrix3Xd& x,
                                                 const Eigen::Vector4i& tet) {
  const auto cross = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d m;
    m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    return m;
  };
  const Eigen::Vector3d origin = x.col(tet[0]);
  std::array<Eigen::Matrix3d, 16> h;
  for (Eigen::Matrix3d& block : h) block.setZero();
  const auto at = [&](int i, int j) -> Eigen::Matrix3d& {
    return h[static_cast<std::size_t>(4 * i + j)];
  };
  // g_i = (x_p - x_0) x (x_q - x_0) / 6 for (i, p, q) cyclic in 1, 2, 3; g_0 = -(g_1 + g_2 + g_3).
  // d(u x w)/du = -[w]x and d(u x w)/dw = [u]x.
  for (int i = 1; i <= 3; ++i) {
    const int p = i % 3 + 1;
    const int q = p % 3 + 1;
    at(i, p) = -cross(x.col(tet[q]) - origin) / 6.0;
    at(i, q) = cross(x.col(tet[p]) - origin) / 6.0;
    at(i, 0) = -(at(i, p) + at(i, q));
  }
  for (int j = 0; j < 4; ++j) at(0, j) = -(at(1, j) + at(2, j) + at(3, j));
  return h;
}

VolumeForceField::VolumeForceField(const SpringMesh& mesh, double bulkModulus_Pa)
    : m_mesh(mesh),
      m_bulkModulus_Pa(bulkModulus_Pa),
      m_cells(groupTetsIntoCells(mesh.restPositions_m, mesh.tets, mesh.tetRestVolume_m3)),
      m_incidence(m_cells, mesh.nodeCount()),
      m_inverseCellRestVolume_1_m3(m_cells.restVolume_m3.cwiseInverse()),
      m_slots{VolumeBlocks::Zero(kVolumeBlockRows, m_cells.cellCount()),
              VolumeBlocks::Zero(kVolumeBlockRows, m_cells.cellCount())},
      m_ownBlocks(VolumeBlocks::Zero(kVolumeBlockRows, m_cells.cellCount())),
      m_pressure_Pa(m_cells.cellCount()) {
  // Room for every tet in each part's list (ints), and for a thousand guarded tets a pass: a
  // deep poke guards a handful; more than a thousand grows the lists once.
  constexpr std::size_t kReservedGuardTerms = 1024;
  m_guardVolume_m3.reserve(m_cells.tets.size());
  for (const int t : m_cells.tets)
    m_guardVolume_m3.push_back(kGuardVolumeRatio * mesh.tetRestVolume_m3[t]);
  for (std::vector<int>& list : m_guardedTets)
    list.reserve(static_cast<std::size_t>(mesh.tets.cols()));
  for (std::size_t slot = 0; slot < 3; ++slot) {
    m_guardTerms[slot].reserve(kReservedGuardTerms);
    m_guardPressure_Pa[slot].reserve(kReservedGuardTerms);
  }
  for (RankOneTermDiagonals& diagonals : m_guardDiagonals)
    diagonals.resize(mesh.nodeCount(), kReservedGuardTerms);
}

VolumeForceField::~VolumeForceField() = default;

void VolumeForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                 const ForcePass& pass, ForceReport& report) const {
  VolumeBlocks* slot = nullptr;
  if (pass.stiffness == StiffnessSlot::Current)
    slot = &m_slots[static_cast<std::size_t>(m_current)];
  if (pass.stiffness == StiffnessSlot::Trial)
    slot = &m_slots[static_cast<std::size_t>(m_current ^ 1)];
  report.volume = addForces(x, f, slot);
  if (pass.nodeStiffness != nullptr) addNodeStiffnessBound(*pass.nodeStiffness);
  if (slot == nullptr) return;
  // The exact Hessian's second part needs the pass's pressures and positions: kept for the
  // assembled matrix, when the pass asks for the exact Hessian (the direct solves; CG asks for
  // the PSD part, and the step loop never comes here).
  const auto index = static_cast<std::size_t>(slot == &m_slots[0] ? 0 : 1);
  m_isSlotExact[index] = !pass.isProjected;
  if (!pass.isProjected) {
    m_slotPressure_Pa[index] = m_pressure_Pa;
    m_slotPositions_m[index] = x;
  }
}

void VolumeForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  for (std::size_t j = 0; j + 1 < m_incidence.start.size(); ++j)
    nodeWork[j] += m_incidence.start[j + 1] - m_incidence.start[j];
}

void VolumeForceField::prepareProducts(const PartBounds& bounds) {
  if (m_product && m_product->bounds() == bounds) return;
  m_product = std::make_unique<VolumeStiffnessProduct>(m_cells, bounds);
}

void VolumeForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  m_product->addPart(part, currentBlocks(), x, y);
  const std::vector<RankOneTerm>& guard = m_guardTerms[static_cast<std::size_t>(m_current)];
  if (guard.empty()) return;
  const PartBounds& bounds = m_product->bounds();
  addRankOneProducts(guard, bounds[static_cast<std::size_t>(part)],
                     bounds[static_cast<std::size_t>(part) + 1], x, y);
}

void VolumeForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  addWeightedDiagonalBlock<false>(j, block);
}

void VolumeForceField::addPreconditionerBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  addWeightedDiagonalBlock<true>(j, block);
}

template <bool IsWeighed>
void VolumeForceField::addWeightedDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  // sqrt(n) for a cell of n nodes (addPreconditionerBlock).
  static constexpr std::array<double, VolumeCells::kMaxNodes + 1> kWeight{0.0,
                                                                          1.0,
                                                                          1.4142135623730951,
                                                                          1.7320508075688772,
                                                                          2.0,
                                                                          2.2360679774997898,
                                                                          2.4494897427086259,
                                                                          2.6457513110645907,
                                                                          2.8284271247461903};
  const auto node = static_cast<std::size_t>(j);
  const VolumeBlocks& blocks = currentBlocks();
  double b00 = 0.0, b01 = 0.0, b02 = 0.0, b11 = 0.0, b12 = 0.0, b22 = 0.0;
  for (int e = m_incidence.start[node]; e < m_incidence.start[node + 1]; ++e) {
    const int entry = m_incidence.entries[static_cast<std::size_t>(e)];
    const int cell = entry / VolumeCells::kMaxNodes;
    const double* const column =
        blocks.data() + kVolumeBlockRows * static_cast<std::ptrdiff_t>(cell);
    const double* const g = column + 3 * (entry % VolumeCells::kMaxNodes);
    double c = column[kVolumeBlockRows - 1];
    if constexpr (IsWeighed)
      c *= kWeight[static_cast<std::size_t>(m_cells.nodeCount[static_cast<std::size_t>(cell)])];
    b00 += c * g[0] * g[0];
    b01 += c * g[0] * g[1];
    b02 += c * g[0] * g[2];
    b11 += c * g[1] * g[1];
    b12 += c * g[1] * g[2];
    b22 += c * g[2] * g[2];
  }
  addSymmetric(block, b00, b01, b02, b11, b12, b22);
  if (m_guardTerms[static_cast<std::size_t>(m_current)].empty()) return;
  if (const Eigen::Matrix3d* guard = m_guardDiagonals[static_cast<std::size_t>(m_current)].at(j))
    block += *guard;
}

void VolumeForceField::addStiffness(NodeBlockMatrix& matrix) const {
  const VolumeBlocks& blocks = currentBlocks();
  for (Eigen::Index c = 0; c < m_cells.cellCount(); ++c) {
    const auto g = blocks.col(c);
    const int count = m_cells.nodeCount[static_cast<std::size_t>(c)];
    for (int i = 0; i < count; ++i) {
      for (int j = 0; j < count; ++j) {
        matrix.addBlock(
            m_cells.nodes(i, c), m_cells.nodes(j, c),
            g[kVolumeBlockRows - 1] * g.segment<3>(3 * i) * g.segment<3>(3 * j).transpose());
      }
    }
  }
  const auto current = static_cast<std::size_t>(m_current);
  addRankOneTerms(m_guardTerms[current], matrix);
  if (!m_isSlotExact[current]) return;
  // p d^2V/dx^2 per tet of each cell, p = kappa (J - 1) the cell's pressure.
  const Eigen::Matrix3Xd& x = m_slotPositions_m[current];
  const Eigen::VectorXd& pressure = m_slotPressure_Pa[current];
  for (Eigen::Index c = 0; c < m_cells.cellCount(); ++c) {
    for (int k = m_cells.tetStart[static_cast<std::size_t>(c)];
         k < m_cells.tetStart[static_cast<std::size_t>(c) + 1]; ++k) {
      const int t = m_cells.tets[static_cast<std::size_t>(k)];
      const std::array<Eigen::Matrix3d, 16> h = tetVolumeHessian(x, m_mesh.tets.col(t));
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          matrix.addBlock(m_mesh.tets(i, t), m_mesh.tets(j, t),
                          pressure[c] * h[static_cast<std::size_t>(4 * i + j)]);
        }
      }
    }
  }
  // The guard's p_t d^2V_t/dx^2.
  const std::vector<RankOneTerm>& guard = m_guardTerms[current];
  for (std::size_t k = 0; k < guard.size(); ++k) {
    const RankOneTerm& term = guard[k];
    const Eigen::Vector4i tet(term.nodes[0], term.nodes[1], term.nodes[2], term.nodes[3]);
    const std::array<Eigen::Matrix3d, 16> h = tetVolumeHessian(x, tet);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        matrix.addBlock(tet[i], tet[j],
                        m_guardPressure_Pa[current][k] * h[static_cast<std::size_t>(4 * i + j)]);
      }
    }
  }
}

VolumeFieldReport VolumeForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                              VolumeBlocks* blocks) const {
  VolumeBlocks& out = blocks != nullptr ? *blocks : m_ownBlocks;
  m_lastBlocks = &out;
  const Eigen::Index cells = m_cells.cellCount();
  std::array<VolumeFieldReport, kParts> parts;
  // Per cell: g summed over its tets, J, k and the pressure; each tet's sign for the report.
  const auto cellPass = [&](int p) {
    // Counted in a local and stored once: the parts' reports share a cache line, and updated
    // per cell from two threads they bounced it between the cores.
    VolumeFieldReport report;
    std::vector<int>& guarded = m_guardedTets[static_cast<std::size_t>(p)];
    guarded.clear();
    const Eigen::Index end = cells * (p + 1) / kParts;
    for (Eigen::Index c = cells * p / kParts; c < end; ++c) {
      // g is summed in registers and on the stack, one scalar per axis and slot, then stored
      // once: summed in place in the column, each tet's vector add read back a slot that the
      // zero fill and the tet before had written with stores of another width and alignment,
      // which the processor cannot forward (the pass's hottest instructions).
      std::array<double, VolumeCells::kMaxNodes> gx{}, gy{}, gz{};
      double volume = 0.0;
      if (m_cells.isCube(c)) {
        volume = addCubeVolumeGradient(x, c, gx, gy, gz, report, guarded);
      } else {
        for (int k = m_cells.tetStart[static_cast<std::size_t>(c)];
             k < m_cells.tetStart[static_cast<std::size_t>(c) + 1]; ++k) {
          const int t = m_cells.tets[static_cast<std::size_t>(k)];
          Eigen::Matrix<double, 3, 4> tetGradient;
          const double tetVolume = signedTetVolumeGradient(x, m_mesh.tets, t, tetGradient.data());
          volume += tetVolume;
          for (int i = 0; i < 4; ++i) {
            const auto slot = static_cast<std::size_t>(m_cells.tetSlots(i, t));
            gx[slot] += tetGradient(0, i);
            gy[slot] += tetGradient(1, i);
            gz[slot] += tetGradient(2, i);
          }
          report.invertedTetCount += tetVolume <= 0.0 ? 1 : 0;
          if (tetVolume < m_guardVolume_m3[static_cast<std::size_t>(k)]) guarded.push_back(t);
        }
      }
      double* const g = out.col(c).data();
      for (std::size_t slot = 0; slot < VolumeCells::kMaxNodes; ++slot) {
        g[3 * slot] = gx[slot];
        g[3 * slot + 1] = gy[slot];
        g[3 * slot + 2] = gz[slot];
      }
      const double inverseRestVolume = m_inverseCellRestVolume_1_m3[c];
      const double ratio = volume * inverseRestVolume;
      report.minVolumeRatio = std::min(report.minVolumeRatio, ratio);
      report.maxVolumeRatio = std::max(report.maxVolumeRatio, ratio);
      g[kVolumeBlockRows - 1] = m_bulkModulus_Pa * inverseRestVolume;
      m_pressure_Pa[c] = m_bulkModulus_Pa * (ratio - 1.0);  // dE/dV
    }
    parts[static_cast<std::size_t>(p)] = report;
  };
  runParts(m_pool, kParts, cellPass);
  // Each node gathers -p_c g_i from its cells, on the pool at any size: a node here reads about
  // eight cells' entries, where the plain node passes read a column or two.
  const int* const start = m_incidence.start.data();
  const int* const entries = m_incidence.entries.data();
  const double* const pressure = m_pressure_Pa.data();
  const double* const blockData = out.data();
  const auto gather = [&](int, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      double f0 = 0.0, f1 = 0.0, f2 = 0.0;
      for (int e = start[j]; e < start[j + 1]; ++e) {
        const int c = entries[e] / VolumeCells::kMaxNodes;
        const double* const gi = blockData + kVolumeBlockRows * static_cast<std::ptrdiff_t>(c) +
                                 3 * (entries[e] % VolumeCells::kMaxNodes);
        f0 += pressure[c] * gi[0];
        f1 += pressure[c] * gi[1];
        f2 += pressure[c] * gi[2];
      }
      forces(0, j) -= f0;
      forces(1, j) -= f1;
      forces(2, j) -= f2;
    }
  };
  forEachNodeRange(m_pool, m_mesh.nodeCount(), gather, 0);
  // The guard, after the cells' forces (on this thread, in the parts' order: the same sums for
  // any thread count).
  const std::size_t guardSlot = &out == &m_slots[0] ? 0 : &out == &m_slots[1] ? 1 : 2;
  addGuardForces(x, forces, m_guardTerms[guardSlot], m_guardPressure_Pa[guardSlot]);
  if (guardSlot < 2) m_guardDiagonals[guardSlot].set(m_guardTerms[guardSlot]);
  m_lastGuardTerms = &m_guardTerms[guardSlot];
  VolumeFieldReport report;
  for (const VolumeFieldReport& part : parts) report.include(part);
  return report;
}

double VolumeForceField::addCubeVolumeGradient(const Eigen::Matrix3Xd& x, Eigen::Index c,
                                               std::array<double, VolumeCells::kMaxNodes>& gx,
                                               std::array<double, VolumeCells::kMaxNodes>& gy,
                                               std::array<double, VolumeCells::kMaxNodes>& gz,
                                               VolumeFieldReport& report,
                                               std::vector<int>& guarded) const {
  // The six tets around the diagonal d = x_7 - x_0 (VolumeCells::cubeSlots), h_k = x_k - x_0:
  //   V_k = d . a_k / 6, a_k = h_k x h_k+1;   V = sum_k V_k
  //   dV/dx_7 = sum_k a_k / 6,   dV/dx_k = d x (h_k-1 - h_k+1) / 6,   dV/dx_0 = -(the others)
  // Each corner is read once: the tet-by-tet sum reads 24 corners and takes 18 cross products.
  constexpr double kSixth = 1.0 / 6.0;
  const auto column = m_cells.nodes.col(c);
  const auto corners = m_cells.cubeSlots.col(c);
  const Eigen::Vector3d low = x.col(column[corners[0]]);
  const Eigen::Vector3d d = x.col(column[corners[7]]) - low;
  // h_k is read from x as the loop reaches it, and rolled through locals: a stack array of the
  // six h_k, written lane by lane and read as vectors, stalled on every read (a store the
  // processor cannot forward to a wider load).
  const auto h = [&](Eigen::Index k) -> Eigen::Vector3d {
    return x.col(column[corners[k + 1]]) - low;
  };
  const auto firstTet = static_cast<std::size_t>(m_cells.tetStart[static_cast<std::size_t>(c)]);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d ringSum = Eigen::Vector3d::Zero();
  double volume = 0.0;
  int inverted = 0;
  const auto addAt = [&](Eigen::Index slot, const Eigen::Vector3d& gi) {
    gx[static_cast<std::size_t>(slot)] = gi.x();
    gy[static_cast<std::size_t>(slot)] = gi.y();
    gz[static_cast<std::size_t>(slot)] = gi.z();
  };
  const Eigen::Vector3d first = h(0);
  Eigen::Vector3d before = h(5);  // h_k-1
  Eigen::Vector3d here = first;   // h_k
  for (std::size_t k = 0; k < 6; ++k) {
    const Eigen::Vector3d after = k < 5 ? h(static_cast<Eigen::Index>(k) + 1) : first;  // h_k+1
    const Eigen::Vector3d a = here.cross(after);
    sum += a;
    const double tetVolume = d.dot(a) * kSixth;
    volume += tetVolume;
    inverted += tetVolume <= 0.0 ? 1 : 0;
    if (tetVolume < m_guardVolume_m3[firstTet + k]) guarded.push_back(m_cells.tets[firstTet + k]);
    const Eigen::Vector3d gk = d.cross(before - after) * kSixth;
    ringSum += gk;
    addAt(corners[static_cast<Eigen::Index>(k) + 1], gk);
    before = here;
    here = after;
  }
  report.invertedTetCount += inverted;
  const Eigen::Vector3d high = sum * kSixth;
  addAt(corners[7], high);
  addAt(corners[0], -(high + ringSum));
  return volume;
}

void VolumeForceField::addGuardForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                      std::vector<RankOneTerm>& terms,
                                      std::vector<double>& pressures) const {
  terms.clear();
  pressures.clear();
  for (const std::vector<int>& guarded : m_guardedTets) {
    for (const int t : guarded) {
      const Eigen::Vector3d a = x.col(m_mesh.tets(0, t));
      const Eigen::Vector3d ab = x.col(m_mesh.tets(1, t)) - a;
      const Eigen::Vector3d ac = x.col(m_mesh.tets(2, t)) - a;
      const Eigen::Vector3d ad = x.col(m_mesh.tets(3, t)) - a;
      RankOneTerm term;
      term.blocks[1] = ac.cross(ad) / 6.0;
      term.blocks[2] = ad.cross(ab) / 6.0;
      term.blocks[3] = ab.cross(ac) / 6.0;
      term.blocks[0] = -(term.blocks[1] + term.blocks[2] + term.blocks[3]);
      const double restVolume = m_mesh.tetRestVolume_m3[t];
      const double ratio = ab.dot(term.blocks[1]) / restVolume;
      const double pressure = m_bulkModulus_Pa * (ratio - kGuardVolumeRatio);  // dE_t/dV_t
      for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
        term.nodes[i] = m_mesh.tets(static_cast<Eigen::Index>(i), t);
        forces.col(term.nodes[i]) -= pressure * term.blocks[i];
      }
      term.stiffness_N_m = m_bulkModulus_Pa / restVolume;
      terms.push_back(term);
      pressures.push_back(pressure);
    }
  }
}

void VolumeForceField::addNodeStiffnessBound(Eigen::VectorXd& nodeStiffness) const {
  if (m_lastGuardTerms != nullptr) {
    for (const RankOneTerm& term : *m_lastGuardTerms) {
      double squaredNorm = 0.0;
      for (const Eigen::Vector3d& block : term.blocks) squaredNorm += block.squaredNorm();
      for (const int node : term.nodes) nodeStiffness[node] += term.stiffness_N_m * squaredNorm;
    }
  }
  const VolumeBlocks& blocks = *m_lastBlocks;
  const int* const start = m_incidence.start.data();
  const int* const entries = m_incidence.entries.data();
  forEachNodeRange(m_pool, m_mesh.nodeCount(), [&](int, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      double sum = 0.0;
      for (int e = start[j]; e < start[j + 1]; ++e) {
        const auto column = blocks.col(entries[e] / VolumeCells::kMaxNodes);
        sum += column[kVolumeBlockRows - 1] * column.head<kVolumeBlockRows - 1>().squaredNorm();
      }
      nodeStiffness[j] += sum;
    }
  });
}

double VolumeForceField::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  for (Eigen::Index c = 0; c < m_cells.cellCount(); ++c) {
    double volume = 0.0;
    for (int k = m_cells.tetStart[static_cast<std::size_t>(c)];
         k < m_cells.tetStart[static_cast<std::size_t>(c) + 1]; ++k)
      volume += signedTetVolume(x, m_mesh.tets, m_cells.tets[static_cast<std::size_t>(k)]);
    const double restVolume = m_cells.restVolume_m3[c];
    const double ratio = volume / restVolume;
    energy += 0.5 * m_bulkModulus_Pa * restVolume * (ratio - 1.0) * (ratio - 1.0);
  }
  for (Eigen::Index t = 0; t < m_mesh.tets.cols(); ++t) {
    const double restVolume = m_mesh.tetRestVolume_m3[t];
    const double below = signedTetVolume(x, m_mesh.tets, t) / restVolume - kGuardVolumeRatio;
    if (below < 0.0) energy += 0.5 * m_bulkModulus_Pa * restVolume * below * below;
  }
  return energy;
}

VolumeFieldReport VolumeForceField::inspect(const SpringMesh& mesh, const Eigen::Matrix3Xd& x,
                                            ForkJoinPool* pool) {
  std::array<VolumeFieldReport, kInspectParts> parts;
  const Eigen::Index tets = mesh.tets.cols();
  const auto part = [&](int p) {
    VolumeFieldReport& report = parts[static_cast<std::size_t>(p)];
    const Eigen::Index end = tets * (p + 1) / kInspectParts;
    for (Eigen::Index t = tets * p / kInspectParts; t < end; ++t) {
      const double ratio = signedTetVolume(x, mesh.tets, t) / mesh.tetRestVolume_m3[t];
      report.minVolumeRatio = std::min(report.minVolumeRatio, ratio);
      report.maxVolumeRatio = std::max(report.maxVolumeRatio, ratio);
      report.invertedTetCount += ratio <= 0.0 ? 1 : 0;
    }
  };
  runParts(pool, kInspectParts, part);
  VolumeFieldReport report;
  for (const VolumeFieldReport& r : parts) report.include(r);
  return report;
}

}  // namespace tissuesim
