// SPDX-License-Identifier: Apache-2.0
// The force-field contract, field by field on one system: each field's forces are minus its
// energy's gradient, and its stiffness (exact where the field has an exact Hessian) is minus the
// forces' derivative; the system's totals are the fields' sums.

#include "forces/ForceField.h"

#include <random>
#include <string>

#include <gtest/gtest.h>

#include "support/TestSystems.h"

namespace tissuesim {
namespace {

struct FieldCase {
  test::BlockSystem block{{0.02, 0.02, 0.02}, {2, 2, 2}, SpringLaw::Eesm, false, 5e4};
  Eigen::Matrix3Xd x;
  Eigen::Matrix3Xd direction;

  FieldCase() {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    x = block.mesh.restPositions_m;
    x.row(0) *= 1.1;  // stretched: the springs on their stiffening branch, the tets larger
    direction.resize(3, x.cols());
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      x.data()[i] += 4e-4 * uniform(random);
      direction.data()[i] = uniform(random);
    }
    block.system.gravity.acceleration_m_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
    PenaltyContact contact;
    const Eigen::Vector4i tet = block.mesh.tets.col(0);
    contact.nodes = {tet[0], tet[1], tet[2], tet[3]};
    contact.weights = {0.1, 0.2, 0.3, 0.4};
    contact.normal = Eigen::Vector3d(0.3, 1.0, -0.2).normalized();
    contact.offset_m = contact.normal.dot(contact.point(x)) - 1e-3;  // 1 mm in
    contact.stiffness_N_m = 2e3;
    block.system.contacts.add(contact);
  }

  Eigen::Matrix3Xd forces(const ForceField& field, const Eigen::Matrix3Xd& at,
                          const ForcePass& pass = {}) const {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, at.cols());
    ForceReport report;
    field.addForces(at, f, pass, report);
    return f;
  }
};

TEST(ForceField, EveryFieldsForceIsMinusItsEnergysGradient) {
  const FieldCase c;
  ASSERT_EQ(c.block.system.fields().size(), 4u) << "springs, volume, gravity, contacts";
  constexpr double h = 1e-7;  // m, along a unit-scale direction
  for (const ForceField* field : c.block.system.fields()) {
    const double slope =
        (field->energy(c.x + h * c.direction) - field->energy(c.x - h * c.direction)) / (2.0 * h);
    const double work = c.forces(*field, c.x).cwiseProduct(c.direction).sum();
    ASSERT_GT(std::abs(work), 1e-6) << field->name() << ": the case exercises it";
    EXPECT_NEAR(slope, -work, 1e-5 * std::abs(work)) << field->name();
  }
}

TEST(ForceField, EveryExactStiffnessIsMinusTheForcesDerivative) {
  // The volume term's K is its Gauss-Newton part only (VolumeForceField.h): checked against its
  // formula in SystemOperator_test, not against the derivative.
  const FieldCase c;
  constexpr double h = 1e-8;
  Eigen::VectorXd flat = Eigen::Map<const Eigen::VectorXd>(c.direction.data(), c.direction.size());
  for (const ForceField* field : c.block.system.fields()) {
    if (std::string(field->name()) == "volume") continue;
    const Eigen::Matrix3Xd df =
        (c.forces(*field, c.x + h * c.direction) - c.forces(*field, c.x - h * c.direction)) /
        (2.0 * h);
    c.forces(*field, c.x, {StiffnessSlot::Current, /*isProjected=*/false});
    NodeBlockMatrix k = c.block.system.makeMatrix();
    k.setZero();
    field->addStiffness(k);
    const Eigen::VectorXd kd = k.matrix() * flat;
    const Eigen::VectorXd expected = -Eigen::Map<const Eigen::VectorXd>(df.data(), df.size());
    const double scale = std::max(expected.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((kd - expected).cwiseAbs().maxCoeff(), 1e-5 * scale) << field->name();
  }
}

TEST(ForceField, TheSystemSumsItsFields) {
  const FieldCase c;
  Eigen::Matrix3Xd total(3, c.x.cols());
  c.block.system.forces(c.x, total);
  Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, c.x.cols());
  for (const ForceField* field : c.block.system.fields()) sum += c.forces(*field, c.x);
  EXPECT_LT((total - sum).cwiseAbs().maxCoeff(), 1e-12 * sum.cwiseAbs().maxCoeff());
  double energy = 0.0;
  for (const ForceField* field : c.block.system.fields()) energy += field->energy(c.x);
  const MechanicalState still{c.x, Eigen::Matrix3Xd::Zero(3, c.x.cols())};
  EXPECT_DOUBLE_EQ(c.block.system.totalEnergy(still), energy);
}

}  // namespace
}  // namespace tissuesim
