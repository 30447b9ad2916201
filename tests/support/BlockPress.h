// SPDX-License-Identifier: Apache-2.0
#pragma once
// A block on its held bottom, the top's nodes within 5 mm of its centre pressed 1 mm down and
// held there, solved to static equilibrium with the tissue's isochoric energy as the FEM
// carries it (per tet or per node) and the volume term (per lattice cube or tet, or per node):
// the force on the pressed nodes (N), for comparing elements and bulk moduli on one mesh.

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "fem/SmoothedStrainForceField.h"
#include "fem/StrainCells.h"
#include "fem/TetIsochoricForceField.h"
#include "mesh/TetMesh.h"
#include "springs/NodalVolumeForceField.h"
#include "springs/SpringForceField.h"
#include "springs/SpringForceLaw.h"
#include "springs/SpringMesh.h"
#include "springs/VolumeForceField.h"
#include "support/TestSystems.h"
#include "system/NewtonSolver.h"

namespace tissuesim::test {

struct BlockPress {
  /// TetIsochoricForceField, or SmoothedStrainForceField on faceStrainCells or nodeStrainCells
  enum class Strain { Tets, Faces, Nodes };
  enum class Volume { Cells, Nodes };  ///< VolumeForceField or NodalVolumeForceField
  Strain strain = Strain::Tets;
  Volume volume = Volume::Nodes;
  double bulkModulus_Pa = 0.0;
};

inline double pressReaction(const TetMesh& mesh, const BlockPress& press) {
  const LiverMaterial& material = LiverMaterial::instance();
  SpringMesh springs = buildSpringMesh(mesh, material.parameters.density_kg_m3);
  springs.volume_m3.setZero();  // the FEM carries the elasticity, as with effects.model fem
  const SpringForceLaw law(SpringLaw::Eesm, material.table, material.parameters,
                           3.0 * material.energy.initialShearModulus(), false);
  SpringForceField springField(springs, law);
  std::unique_ptr<ForceField> isochoric;
  if (press.strain == BlockPress::Strain::Tets) {
    isochoric = std::make_unique<TetIsochoricForceField>(mesh.nodes_m, mesh.tets, material.energy);
  } else {
    isochoric = std::make_unique<SmoothedStrainForceField>(
        press.strain == BlockPress::Strain::Faces ? faceStrainCells(mesh.nodes_m, mesh.tets)
                                                  : nodeStrainCells(mesh.nodes_m, mesh.tets),
        mesh.nodes_m.cols(), material.energy);
  }
  std::unique_ptr<VolumeForceField> cells;
  std::unique_ptr<NodalVolumeForceField> nodes;
  if (press.volume == BlockPress::Volume::Cells) {
    cells = std::make_unique<VolumeForceField>(springs, press.bulkModulus_Pa);
  }
  MechanicalSystem system(springField, cells.get());
  system.addField(*isochoric);
  if (press.volume == BlockPress::Volume::Nodes) {
    nodes = std::make_unique<NodalVolumeForceField>(mesh.nodes_m, mesh.tets, press.bulkModulus_Pa);
    system.addField(*nodes);
  }
  const Eigen::Vector3d top = mesh.nodes_m.rowwise().maxCoeff();
  Eigen::Matrix3Xd x = mesh.nodes_m;
  std::vector<int> pressed;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (x(2, i) < 1e-9) system.fixNode(static_cast<int>(i));
    const double fromAxis = std::hypot(x(0, i) - 0.5 * top.x(), x(1, i) - 0.5 * top.y());
    if (x(2, i) > top.z() - 1e-9 && fromAxis < 5e-3) {
      system.fixNode(static_cast<int>(i));
      x(2, i) -= 1e-3;
      pressed.push_back(static_cast<int>(i));
    }
  }
  NewtonSolver newton(LinearSolverKind::Cholesky);
  const Eigen::Matrix3Xd start = x;
  const NewtonReport report = newton.solve(system, x, start, 0.0, 0.0, 100, 1e-10);
  EXPECT_TRUE(report.converged) << "kappa " << press.bulkModulus_Pa;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport seen;
  for (const ForceField* field : system.fields()) field->addForces(x, f, ForcePass{}, seen);
  double reaction = 0.0;
  for (const int i : pressed) reaction += f(2, i);
  return reaction;
}

}  // namespace tissuesim::test
