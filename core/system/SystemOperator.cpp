// SPDX-License-Identifier: Apache-2.0
#include "system/SystemOperator.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace tissuesim {

SystemOperator::SystemOperator(MechanicalSystem& system)
    : m_mass_kg(system.mesh().nodeMass_kg),
      m_fields(system.fields()),
      m_isFixed(static_cast<std::size_t>(3 * system.mesh().nodeCount()), 0) {
  const Eigen::Index nodes = system.mesh().nodeCount();
  if (3 * nodes > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("SystemOperator: " + std::to_string(nodes) +
                                " nodes (rows must fit an int)");
  }
  std::vector<Eigen::Index> nodeWork(static_cast<std::size_t>(nodes), 0);
  for (const ForceField* field : m_fields) field->addProductWork(nodeWork);
  std::vector<Eigen::Index> workBefore(static_cast<std::size_t>(nodes) + 1, 0);
  for (std::size_t j = 0; j < nodeWork.size(); ++j) workBefore[j + 1] = workBefore[j] + nodeWork[j];
  m_bounds = balancedPartBounds(
      nodes, [&](Eigen::Index j) { return workBefore[static_cast<std::size_t>(j)]; });
  system.prepareProducts(m_bounds);
  m_fixedStart.fill(0);
}

void SystemOperator::setFixedDofs(const std::vector<char>& isFixed) {
  if (isFixed.size() != m_isFixed.size()) {
    throw std::invalid_argument("SystemOperator: " + std::to_string(isFixed.size()) +
                                " DOF flags for " + std::to_string(m_isFixed.size()) + " DOFs");
  }
  if (isFixed == m_isFixed) return;
  m_isFixed = isFixed;
  m_fixedDofs.clear();
  for (std::size_t p = 0; p < kParts; ++p) {
    m_fixedStart[p] = m_fixedDofs.size();
    for (Eigen::Index d = 3 * m_bounds[p]; d < 3 * m_bounds[p + 1]; ++d) {
      if (m_isFixed[static_cast<std::size_t>(d)] != 0) m_fixedDofs.push_back(d);
    }
  }
  m_fixedStart[kParts] = m_fixedDofs.size();
}

void SystemOperator::multiplyPart(int part, const double* x, double* y) const {
  const auto p = static_cast<std::size_t>(part);
  const double* const mass = m_mass_kg.data();
  for (Eigen::Index j = m_bounds[p]; j < m_bounds[p + 1]; ++j) {
    const double weight = m_massWeight * mass[j] + m_shift_N_m;  // as Newton adds it to a matrix
    for (Eigen::Index d = 3 * j; d < 3 * j + 3; ++d) y[d] = weight * x[d];
  }
  for (const ForceField* field : m_fields) field->addStiffnessProduct(part, x, y);
  for (std::size_t i = m_fixedStart[p]; i < m_fixedStart[p + 1]; ++i)
    y[m_fixedDofs[i]] = x[m_fixedDofs[i]];
}

Eigen::Matrix3d SystemOperator::diagonalBlock(Eigen::Index j) const {
  return sumOfBlocks(j, &ForceField::addDiagonalBlock);
}

Eigen::Matrix3d SystemOperator::preconditionerBlock(Eigen::Index j) const {
  return sumOfBlocks(j, &ForceField::addPreconditionerBlock);
}

Eigen::Matrix3d SystemOperator::sumOfBlocks(Eigen::Index j, AddBlock addBlock) const {
  Eigen::Matrix3d block = Eigen::Matrix3d::Identity() * (m_massWeight * m_mass_kg[j] + m_shift_N_m);
  for (const ForceField* field : m_fields) (field->*addBlock)(j, block);
  const auto node = static_cast<std::size_t>(j);
  for (int c = 0; c < 3; ++c) {
    if (m_isFixed[3 * node + static_cast<std::size_t>(c)] == 0) continue;
    block.row(c).setZero();
    block.col(c).setZero();
    block(c, c) = 1.0;
  }
  return block;
}

double SystemOperator::largestDiagonalEntry() const {
  double largest = 0.0;
  for (Eigen::Index j = 0; j < nodeCount(); ++j)
    largest = std::max(largest, diagonalBlock(j).diagonal().maxCoeff());
  return largest;
}

}  // namespace tissuesim
