// SPDX-License-Identifier: Apache-2.0
#pragma once
// Gravity on the lumped masses:
//
//   f_j = m_j g (N),   E = -sum_j m_j g . x_j (J),   K = 0
//
// m_j (kg, #V) the nodes' lumped masses, g (m/s^2) the scene's. With g = 0 (a weightless scene)
// a pass does nothing.

#include <Eigen/Core>

#include "forces/ForceField.h"

namespace tissuesim {

class GravityForceField final : public ForceField {
 public:
  /// `mass_kg` (#V) must outlive this object.
  explicit GravityForceField(const Eigen::VectorXd& mass_kg) : m_mass_kg(mass_kg) {}

  Eigen::Vector3d acceleration_m_s2 = Eigen::Vector3d::Zero();

  const char* name() const override { return "gravity"; }
  double energy(const Eigen::Matrix3Xd& x) const override {
    return -(x.transpose() * acceleration_m_s2).dot(m_mass_kg);
  }
  void addForces(const Eigen::Matrix3Xd&, Eigen::Matrix3Xd& f, const ForcePass&,
                 ForceReport&) const override {
    if (acceleration_m_s2.isZero(0.0)) return;
    f.noalias() += acceleration_m_s2 * m_mass_kg.transpose();
  }
  void addStiffnessProduct(int, const double*, double*) const override {}
  void addDiagonalBlock(Eigen::Index, Eigen::Matrix3d&) const override {}
  void addStiffness(NodeBlockMatrix&) const override {}

 private:
  const Eigen::VectorXd& m_mass_kg;
};

}  // namespace tissuesim
