// SPDX-License-Identifier: Apache-2.0
#include "system/MechanicalSystem.h"

#include <vector>

#include "parallel/NodeRanges.h"
#include "springs/StiffnessCouplings.h"

namespace tissuesim {

MechanicalSystem::MechanicalSystem(SpringForceField& springs, VolumeForceField* volume)
    : gravity(springs.mesh().nodeMass_kg),
      externalForces_N(Eigen::Matrix3Xd::Zero(3, springs.mesh().nodeCount())),
      m_springs(springs),
      m_volume(volume),
      m_isFixed(static_cast<std::size_t>(3 * springs.mesh().nodeCount()), 0) {
  m_mutableFields.push_back(&m_springs);
  if (m_volume != nullptr) m_mutableFields.push_back(m_volume);
  m_mutableFields.push_back(&gravity);
  m_mutableFields.push_back(&contacts);
  m_fields.assign(m_mutableFields.begin(), m_mutableFields.end());
}

void MechanicalSystem::addField(ForceField& field) {
  m_mutableFields.insert(m_mutableFields.end() - 1, &field);  // the contacts stay last
  m_fields.assign(m_mutableFields.begin(), m_mutableFields.end());
}

void MechanicalSystem::prepareProducts(const ForceField::PartBounds& bounds) {
  for (ForceField* field : m_mutableFields) field->prepareProducts(bounds);
}

NodeBlockMatrix MechanicalSystem::makeMatrix() const {
  std::vector<Eigen::Matrix2Xi> fieldPairs;
  Eigen::Index count = 0;
  for (const ForceField* field : m_fields) {
    fieldPairs.push_back(field->couplings());
    count += fieldPairs.back().cols();
  }
  Eigen::Matrix2Xi pairs(2, count);
  count = 0;
  for (const Eigen::Matrix2Xi& each : fieldPairs) {
    pairs.middleCols(count, each.cols()) = each;
    count += each.cols();
  }
  return NodeBlockMatrix(mesh().nodeCount(), stiffnessCouplings(mesh(), pairs));
}

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

void MechanicalSystem::addExternalAndZeroFixed(Eigen::Matrix3Xd& f) const {
  forEachNodeRange(threadPool(), f.cols(), [&](int, Eigen::Index begin, Eigen::Index end) {
    f.middleCols(begin, end - begin) += externalForces_N.middleCols(begin, end - begin);
    double* flat = f.data();
    for (Eigen::Index d = 3 * begin; d < 3 * end; ++d) {
      if (m_isFixed[static_cast<std::size_t>(d)] != 0) flat[d] = 0.0;
    }
  });
}

ForceReport MechanicalSystem::forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                     const ForcePass& pass) const {
  f.setZero();
  ForcePass ours = pass;
  ours.fixedDofs = &m_isFixed;
  ForceReport report;
  for (const ForceField* field : m_fields) field->addForces(x, f, ours, report);
  addExternalAndZeroFixed(f);
  return report;
}

ForceReport MechanicalSystem::forcesAndNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                                     Eigen::VectorXd& nodeStiffness) const {
  f.setZero();
  nodeStiffness.setZero();
  ForcePass pass;
  pass.fixedDofs = &m_isFixed;
  pass.nodeStiffness = &nodeStiffness;
  ForceReport report;
  for (const ForceField* field : m_fields) {
    if (field != &contacts) field->addForces(x, f, pass, report);
  }
  addExternalAndZeroFixed(f);
  return report;
}

void MechanicalSystem::acceptTrialStiffness() const {
  for (const ForceField* field : m_fields) field->acceptTrialStiffness();
}

void MechanicalSystem::assembleStiffness(NodeBlockMatrix& matrix) const {
  matrix.setZero();
  for (const ForceField* field : m_fields) field->addStiffness(matrix);
}

double MechanicalSystem::totalEnergy(const MechanicalState& state) const {
  double energy = 0.0;
  const Eigen::VectorXd& mass = mesh().nodeMass_kg;
  for (Eigen::Index i = 0; i < mesh().nodeCount(); ++i)
    energy += 0.5 * mass[i] * state.v.col(i).squaredNorm();
  for (const ForceField* field : m_fields) energy += field->energy(state.x);
  return energy;
}

}  // namespace tissuesim
