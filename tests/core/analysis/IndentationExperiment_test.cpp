// SPDX-License-Identifier: Apache-2.0
// The indentation test: the probe's penalty is its energy's gradient through both of its
// interfaces, the FEM's force converges as the grid is refined towards the probe, and the spring
// network's sampled surface meets the probe between its nodes.

#include "analysis/IndentationExperiment.h"

#include <random>
#include <string>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "forces/CapsulePenalty.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

TEST(CapsulePenalty, ItsForcesAreItsEnergysGradientThroughBothInterfaces) {
  // Three points pressed into a probe: a node alone, and two points of one triangle.
  Eigen::Matrix3Xd x(3, 4);
  x << 0.0, 0.002, 0.0, 0.001,  //
      0.0, 0.0, 0.002, 0.0005,  //
      0.0, 0.0, 0.0, 0.0;
  CapsulePenalty probe({{{3, 3, 3}, {1.0, 0.0, 0.0}, 2e3},
                        {{0, 1, 2}, {0.5, 0.3, 0.2}, 3e3},
                        {{0, 1, 2}, {0.2, 0.2, 0.6}, 1e3}});
  probe.tip_m = Eigen::Vector3d(0.0008, 0.0006, 0.0022);
  probe.top_m = probe.tip_m + Eigen::Vector3d(0.0, 0.0, 0.3);
  probe.radius_m = 0.0025;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 4);
  ForceReport report;
  probe.addForces(x, f, {}, report);
  Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, 4);
  const double energy = probe.add(x, &gradient, nullptr);
  EXPECT_DOUBLE_EQ(energy, probe.energy(x));
  EXPECT_LT((f + gradient).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((probe.reaction(x) + f.rowwise().sum()).cwiseAbs().maxCoeff(), 1e-12);
  std::mt19937 random(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Matrix3Xd direction(3, 4);
  for (Eigen::Index i = 0; i < direction.size(); ++i) direction.data()[i] = uniform(random);
  constexpr double h = 1e-9;
  const double slope =
      (probe.energy(x + h * direction) - probe.energy(x - h * direction)) / (2.0 * h);
  const double expected = gradient.cwiseProduct(direction).sum();
  ASSERT_GT(std::abs(expected), 1e-3);
  EXPECT_NEAR(slope, expected, 1e-6 * std::abs(expected));
}

IndentationSetup smallBlock() {
  IndentationSetup setup;
  setup.size_m = {0.01, 0.01, 0.005};
  setup.depths_m = {0.0005};
  return setup;
}

TEST(Indentation, TheFemForceConvergesAsTheGridIsRefined) {
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  std::vector<double> forces;
  for (const int refinement : {1, 2, 4}) {
    const IndentationCurve curve = indentFem(energy, smallBlock(), refinement, kappa);
    EXPECT_EQ(curve.unconvergedPoints, 0) << refinement;
    ASSERT_GT(curve.force_N[0], 0.0);
    forces.push_back(curve.force_N[0]);
  }
  // Each refinement changes the force less than the one before (by a factor of 2 at least).
  EXPECT_LT(std::abs(forces[2] - forces[1]), 0.5 * std::abs(forces[1] - forces[0]));
}

TEST(Indentation, TheNetworksSurfaceMeetsTheProbeBetweenItsNodes) {
  // About 1,000 springs on the small block: 1.3 mm between nodes, while the probe's footprint at
  // 0.5 mm is about 1.6 mm across. The sampled surface carries the probe whether or not a node
  // lies under it; the force is of the FEM's order.
  const test::LiverMaterial& material = test::LiverMaterial::instance();
  const IndentationCurve springs =
      indentSprings(material.energy, material.table, smallBlock(),
                    {indentationCellEdge(smallBlock(), 1000), SpringLaw::Eesm, 0.0});
  const IndentationCurve fem =
      indentFem(material.energy, smallBlock(), 2, defaultFemBulkModulus(material.energy));
  EXPECT_GT(springs.force_N[0], fem.force_N[0] / 3.0);
  EXPECT_LT(springs.force_N[0], fem.force_N[0] * 3.0);
}

TEST(Indentation, TheIsochoricTetsConvergeOnTheFemFromAboveAsTheLatticeIsRefined) {
  // The tissue's energy per linear tet with the volume term per cube, at the FEM's bulk
  // modulus, is a conforming discretisation of the same continuum: too stiff on a coarse
  // lattice, and closer with every refinement (where the springs' network is not: see
  // docs/performance.md).
  const test::LiverMaterial& material = test::LiverMaterial::instance();
  const double kappa = defaultFemBulkModulus(material.energy);
  const double fem = indentFem(material.energy, smallBlock(), 2, kappa).force_N[0];
  std::vector<double> errors;
  // Lattices of 5, 9 and 13 cubes across: the probe's axis through a cube's middle in each (the
  // parity of the count changes which nodes meet the probe, and the force with it).
  for (const int springs : {400, 3000, 8000}) {
    IndentationNetwork network{indentationCellEdge(smallBlock(), springs), SpringLaw::Eesm, kappa};
    network.model = LatticeModel::IsochoricTets;
    const IndentationCurve curve =
        indentSprings(material.energy, material.table, smallBlock(), network);
    EXPECT_EQ(curve.unconvergedPoints, 0) << springs;
    EXPECT_GT(curve.force_N[0], fem) << springs;
    errors.push_back(curve.force_N[0] / fem - 1.0);
  }
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
}

TEST(Indentation, TheTopFaceUnderTheProbeSinksByTheDepthInBothModels) {
  // The samples from the axis outwards: under the probe the top face follows the probe's tip
  // down (the penalty lets it in by micrometres; the network's flat triangles, whose points are
  // pushed onto the tip's sphere, may stand off it by up to the chord's sag h^2 / 8R); 4 mm out
  // it has sunk far less.
  const test::LiverMaterial& material = test::LiverMaterial::instance();
  IndentationSetup setup = smallBlock();
  setup.surfaceSamples_m = {{0.0, 0.0}, {0.004, 0.0}};
  const double depth = setup.depths_m.back();
  const double cell = indentationCellEdge(setup, 3000);
  const IndentationCurve fem =
      indentFem(material.energy, setup, 2, defaultFemBulkModulus(material.energy));
  const IndentationCurve springs =
      indentSprings(material.energy, material.table, setup, {cell, SpringLaw::Eesm, 0.0});
  const double sag = cell * cell / (8.0 * setup.probeRadius_m);
  ASSERT_EQ(fem.surfaceDisplacement_m.size(), 2u);
  ASSERT_EQ(springs.surfaceDisplacement_m.size(), 2u);
  EXPECT_NEAR(fem.surfaceDisplacement_m[0].z(), -depth, 0.02 * depth);
  EXPECT_NEAR(springs.surfaceDisplacement_m[0].z(), -depth, 0.02 * depth + sag);
  for (const IndentationCurve* curve : {&fem, &springs})
    EXPECT_GT(curve->surfaceDisplacement_m[1].z(), 0.5 * curve->surfaceDisplacement_m[0].z());
}

TEST(Indentation, ASlowPokeAtPaceMeetsTheStaticForce) {
  // 1 cm/s: inertia and damping are negligible, so the force as the probe passes the depth is
  // the static equilibrium's. The implicit integrator meets it within 3 %. The explicit one
  // applies the contacts as impulses, each solved for its own point: a node that many points
  // share is pushed a few micrometres past the probe's surface (8 um here, at 0.47 mm), and the
  // mean impulse reads 13 % high, as slowly as 1 mm/s; held within 15 %.
  const test::LiverMaterial& material = test::LiverMaterial::instance();
  const IndentationSetup setup = smallBlock();
  const IndentationNetwork network{indentationCellEdge(setup, 1000), SpringLaw::Eesm, 0.0};
  const IndentationCurve statics = indentSprings(material.energy, material.table, setup, network);
  for (const char* integrator : {"implicit", "explicit"}) {
    IndentationPace pace;
    pace.integrator = integrator;
    pace.speed_m_s = 0.01;
    pace.settings.maxIterations = 20;
    pace.settings.linearTolerance = 1e-10;
    pace.settings.forceTolerance_N = 1e-9;
    pace.settings.massDamping_1_s = 5.0;
    const IndentationCurve paced = indentSpringsAtPace(material.energy, material.table, setup,
                                                       network, pace, sampledTopFaceContact(setup));
    ASSERT_EQ(paced.force_N.size(), 1u) << integrator;
    EXPECT_EQ(paced.failedSteps, 0) << integrator;
    const double tolerance = std::string(integrator) == "implicit" ? 0.03 : 0.15;
    EXPECT_NEAR(paced.force_N[0], statics.force_N[0], tolerance * statics.force_N[0]) << integrator;
    EXPECT_NEAR(paced.surfaceDisplacement_m[0].z(), statics.surfaceDisplacement_m[0].z(),
                0.03 * setup.depths_m[0])
        << integrator;
  }
  IndentationPace unknown;
  unknown.integrator = "no-such-scheme";
  EXPECT_THROW(indentSpringsAtPace(material.energy, material.table, setup, network, unknown,
                                   sampledTopFaceContact(setup)),
               std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
