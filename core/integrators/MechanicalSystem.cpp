#include "integrators/MechanicalSystem.h"

#include <cmath>
#include <stdexcept>

#include "parallel/NodeRanges.h"

namespace tissuesim {

MechanicalSystem::MechanicalSystem(SpringForceField& springs, const VolumeForceField* volume)
    : externalForces_N(Eigen::Matrix3Xd::Zero(3, springs.mesh().nodeCount())),
      m_springs(springs),
      m_volume(volume),
      m_isFixed(static_cast<std::size_t>(3 * springs.mesh().nodeCount()), 0),
      m_springBlocks(5, springs.mesh().springCount()),
      m_volumeBlocks(13, volume != nullptr ? springs.mesh().tets.cols() : 0) {}

MechanicalState MechanicalSystem::restState() const {
  return {mesh().restPositions_m, Eigen::Matrix3Xd::Zero(3, mesh().nodeCount())};
}

void MechanicalSystem::fixNode(int node) {
  for (int axis = 0; axis < 3; ++axis) m_isFixed[static_cast<std::size_t>(3 * node + axis)] = 1;
  ++m_constraintRevision;
}

void MechanicalSystem::fixDof(int node, int axis) {
  m_isFixed[static_cast<std::size_t>(3 * node + axis)] = 1;
  ++m_constraintRevision;
}

void MechanicalSystem::releaseAll() {
  std::fill(m_isFixed.begin(), m_isFixed.end(), 0);
  ++m_constraintRevision;
}

// x: where the contacts are evaluated; null leaves them out.
void MechanicalSystem::addExternalAndZeroFixed(const Eigen::Matrix3Xd* x,
                                               Eigen::Matrix3Xd& f) const {
  // The contacts (a few nodes) first, then one node-wise pass for the rest.
  if (x != nullptr) contacts.addForces(*x, f);
  const Eigen::VectorXd& mass = mesh().nodeMass_kg;
  forEachNodeRange(m_springs.threadPool(), f.cols(),
                   [&](int, Eigen::Index begin, Eigen::Index end) {
                     for (Eigen::Index i = begin; i < end; ++i)
                       f.col(i) += mass[i] * gravity_m_s2 + externalForces_N.col(i);
                     double* flat = f.data();
                     for (Eigen::Index d = 3 * begin; d < 3 * end; ++d) {
                       if (m_isFixed[static_cast<std::size_t>(d)] != 0) flat[d] = 0.0;
                     }
                   });
}

ForceReport MechanicalSystem::forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const {
  f.setZero();
  ForceReport report;
  report.springs = m_springs.addForces(x, f);
  if (m_volume != nullptr) report.volume = m_volume->addForces(x, f);
  addExternalAndZeroFixed(&x, f);
  return report;
}

ForceReport MechanicalSystem::forcesAndNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                                     Eigen::VectorXd& nodeStiffness) const {
  f.setZero();
  ForceReport report;
  report.springs = m_springs.addForcesAndNodeStiffness(x, f, nodeStiffness);
  if (m_volume != nullptr) {
    report.volume = m_volume->addForces(x, f);
    m_volume->addNodeStiffnessBound(nodeStiffness);
  }
  addExternalAndZeroFixed(nullptr, f);
  return report;
}

ForceReport MechanicalSystem::forcesAndStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                                 NodeBlockMatrix& stiffness,
                                                 bool isProjected) const {
  f.setZero();
  ForceReport report;
  report.springs = m_springs.addForcesAndStiffness(x, f, m_springBlocks, isProjected);
  // The matrix's edges are the springs, in order (makeMatrix).
  if (stiffness.edgeCount() != m_springBlocks.cols()) {
    throw std::logic_error(
        "MechanicalSystem::forcesAndStiffness: the matrix is not makeMatrix()'s");
  }
  // Every value, no clearing first; on the springs' pool.
  stiffness.assignAxialEdgeStiffness(m_springBlocks, m_springs.threadPool());
  if (m_volume != nullptr) {
    report.volume = m_volume->addForces(x, f, &m_volumeBlocks);
    for (Eigen::Index t = 0; t < mesh().tets.cols(); ++t) {
      const auto g = m_volumeBlocks.col(t);
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          stiffness.addBlock(mesh().tets(i, t), mesh().tets(j, t),
                             g[12] * g.segment<3>(3 * i) * g.segment<3>(3 * j).transpose());
        }
      }
    }
  }
  contacts.addStiffness(x, stiffness);
  addExternalAndZeroFixed(&x, f);
  return report;
}

ForceReport MechanicalSystem::forcesAndLinearization(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                                     SystemLinearization& linearization,
                                                     bool isProjected) const {
  f.setZero();
  ForceReport report;
  report.springs = m_springs.addForcesAndStiffness(x, f, linearization.springs, isProjected);
  if (m_volume != nullptr) report.volume = m_volume->addForces(x, f, &linearization.volume);
  addExternalAndZeroFixed(&x, f);
  return report;
}

SystemLinearization MechanicalSystem::makeLinearization() const {
  return {AxialBlocks(5, mesh().springCount()),
          VolumeBlocks(13, m_volume != nullptr ? mesh().tets.cols() : 0)};
}

double MechanicalSystem::totalEnergy(const MechanicalState& state) const {
  const SpringMesh& m = mesh();
  double energy = 0.0;
  for (Eigen::Index i = 0; i < m.nodeCount(); ++i) {
    energy += 0.5 * m.nodeMass_kg[i] * state.v.col(i).squaredNorm();
    energy -= m.nodeMass_kg[i] * gravity_m_s2.dot(state.x.col(i));
  }
  // Elastic energy V_e W(lambda), W = integral of P from 1: the spring law's own energy.
  for (Eigen::Index s = 0; s < m.springCount(); ++s) {
    const double lambda =
        (state.x.col(m.springs(1, s)) - state.x.col(m.springs(0, s))).norm() / m.restLength_m[s];
    // Simpson's rule on [1, lambda] (16 panels): accurate for any of the three laws.
    constexpr int kPanels = 16;
    const double h = (lambda - 1.0) / kPanels;
    double sum = 0.0;
    for (int k = 0; k <= kPanels; ++k) {
      const double weight = (k == 0 || k == kPanels) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
      sum += weight * m_springs.law().evaluate(1.0 + k * h, 1.0).stress;
    }
    energy += m.volume_m3[s] * sum * h / 3.0;
  }
  if (m_volume != nullptr) energy += m_volume->energy(state.x);
  return energy;
}

}  // namespace tissuesim
