#include "springs/VolumeForceField.h"

#include <algorithm>
#include <array>

#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"
#include "numerics/SymmetricBlock.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

VolumeForceField::VolumeForceField(const SpringMesh& mesh, double bulkModulus_Pa)
    : m_mesh(mesh),
      m_bulkModulus_Pa(bulkModulus_Pa),
      m_incidence(mesh.tets, mesh.nodeCount()),
      m_inverseRestVolume_1_m3(mesh.tetRestVolume_m3.cwiseInverse()),
      m_slots{VolumeBlocks(13, mesh.tets.cols()), VolumeBlocks(13, mesh.tets.cols())},
      m_ownBlocks(13, mesh.tets.cols()),
      m_pressure_Pa(mesh.tets.cols()) {}

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
}

void VolumeForceField::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  for (std::size_t j = 0; j + 1 < m_incidence.start.size(); ++j)
    nodeWork[j] += m_incidence.start[j + 1] - m_incidence.start[j];
}

void VolumeForceField::prepareProducts(const PartBounds& bounds) {
  if (m_product && m_product->bounds() == bounds) return;
  m_product = std::make_unique<TetStiffnessProduct>(m_mesh.tets, bounds);
}

void VolumeForceField::addStiffnessProduct(int part, const double* x, double* y) const {
  m_product->addPart(part, currentBlocks(), x, y);
}

void VolumeForceField::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  const auto node = static_cast<std::size_t>(j);
  const VolumeBlocks& blocks = currentBlocks();
  double b00 = 0.0, b01 = 0.0, b02 = 0.0, b11 = 0.0, b12 = 0.0, b22 = 0.0;
  for (int e = m_incidence.start[node]; e < m_incidence.start[node + 1]; ++e) {
    const int entry = m_incidence.entries[static_cast<std::size_t>(e)];
    const double* const column = blocks.data() + 13 * static_cast<std::ptrdiff_t>(entry >> 2);
    const double* const g = column + 3 * (entry & 3);
    const double c = column[12];
    b00 += c * g[0] * g[0];
    b01 += c * g[0] * g[1];
    b02 += c * g[0] * g[2];
    b11 += c * g[1] * g[1];
    b12 += c * g[1] * g[2];
    b22 += c * g[2] * g[2];
  }
  addSymmetric(block, b00, b01, b02, b11, b12, b22);
}

void VolumeForceField::addStiffness(NodeBlockMatrix& matrix) const {
  const VolumeBlocks& blocks = currentBlocks();
  for (Eigen::Index t = 0; t < m_mesh.tets.cols(); ++t) {
    const auto g = blocks.col(t);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        matrix.addBlock(m_mesh.tets(i, t), m_mesh.tets(j, t),
                        g[12] * g.segment<3>(3 * i) * g.segment<3>(3 * j).transpose());
      }
    }
  }
}

VolumeFieldReport VolumeForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                              VolumeBlocks* blocks) const {
  VolumeBlocks& out = blocks != nullptr ? *blocks : m_ownBlocks;
  m_lastBlocks = &out;
  const Eigen::Index tets = m_mesh.tets.cols();
  std::array<VolumeFieldReport, kParts> parts;
  // Per tet: g, c and the pressure.
  const auto tetPass = [&](int p) {
    VolumeFieldReport& report = parts[static_cast<std::size_t>(p)];
    const Eigen::Index end = tets * (p + 1) / kParts;
    for (Eigen::Index t = tets * p / kParts; t < end; ++t) {
      const Eigen::Vector3d a = x.col(m_mesh.tets(0, t));
      const Eigen::Vector3d ab = x.col(m_mesh.tets(1, t)) - a;
      const Eigen::Vector3d ac = x.col(m_mesh.tets(2, t)) - a;
      const Eigen::Vector3d ad = x.col(m_mesh.tets(3, t)) - a;
      double* const g = out.col(t).data();
      Eigen::Map<Eigen::Vector3d> g0(g), g1(g + 3), g2(g + 6), g3(g + 9);
      g1 = ac.cross(ad) / 6.0;
      g2 = ad.cross(ab) / 6.0;
      g3 = ab.cross(ac) / 6.0;
      g0 = -(g1 + g2 + g3);
      const double inverseRestVolume = m_inverseRestVolume_1_m3[t];
      const double ratio = ab.dot(g1) * inverseRestVolume;  // V = (x_b - x_a) . g_b
      g[12] = m_bulkModulus_Pa * inverseRestVolume;
      m_pressure_Pa[t] = m_bulkModulus_Pa * (ratio - 1.0);  // dE/dV
      report.minVolumeRatio = std::min(report.minVolumeRatio, ratio);
      report.maxVolumeRatio = std::max(report.maxVolumeRatio, ratio);
      report.invertedTetCount += ratio <= 0.0 ? 1 : 0;
    }
  };
  runParts(m_pool, kParts, tetPass);
  // Each node gathers -p_t g_i from its tets.
  const int* const start = m_incidence.start.data();
  const int* const entries = m_incidence.entries.data();
  const double* const pressure = m_pressure_Pa.data();
  const double* const blockData = out.data();
  forEachNodeRange(m_pool, m_mesh.nodeCount(), [&](int, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      double f0 = 0.0, f1 = 0.0, f2 = 0.0;
      for (int e = start[j]; e < start[j + 1]; ++e) {
        const int t = entries[e] >> 2;
        const double* const gi =
            blockData + 13 * static_cast<std::ptrdiff_t>(t) + 3 * (entries[e] & 3);
        f0 += pressure[t] * gi[0];
        f1 += pressure[t] * gi[1];
        f2 += pressure[t] * gi[2];
      }
      forces(0, j) -= f0;
      forces(1, j) -= f1;
      forces(2, j) -= f2;
    }
  });
  VolumeFieldReport report;
  for (const VolumeFieldReport& part : parts) report.include(part);
  return report;
}

void VolumeForceField::addNodeStiffnessBound(Eigen::VectorXd& nodeStiffness) const {
  const VolumeBlocks& blocks = *m_lastBlocks;
  const int* const start = m_incidence.start.data();
  const int* const entries = m_incidence.entries.data();
  forEachNodeRange(m_pool, m_mesh.nodeCount(), [&](int, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      double sum = 0.0;
      for (int e = start[j]; e < start[j + 1]; ++e) {
        const auto column = blocks.col(entries[e] >> 2);
        sum += column[12] * column.head<12>().squaredNorm();
      }
      nodeStiffness[j] += sum;
    }
  });
}

double VolumeForceField::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  for (Eigen::Index t = 0; t < m_mesh.tets.cols(); ++t) {
    const double restVolume = m_mesh.tetRestVolume_m3[t];
    const double ratio = signedTetVolume(x, m_mesh.tets, t) / restVolume;
    energy += 0.5 * m_bulkModulus_Pa * restVolume * (ratio - 1.0) * (ratio - 1.0);
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
