// SPDX-License-Identifier: Apache-2.0
#pragma once
// The organ poke's continuum reference: the organ meshed conformally with its drawn surface (a
// tet mesh whose boundary is that surface, made offline by a mesher: assets/meshes/README.md),
// its tets made quadratic with one dilatation each (fem/FemModel.h, the indentation test's
// reference element), the nodes in the scene's fixed box held, weightless; the probe (a capsule
// along the instrument's axis) lowered quasi-statically into the point where its axis first
// meets the surface, and the force along the axis on it at each depth below that point.
//
// The probe pushes the surface's quadratic nodes near that point by a penalty per unit area
// (CapsulePenalty, as the indentation test's FEM): each node carries its share of the surface,
// the boundary's faces cut into four at their edges' midpoints. Every depth is a converged static
// equilibrium (Newton with the exact Hessian, CHOLMOD). Monotonic loading: no softening.

#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // AlignedBox

#include "analysis/IndentationExperiment.h"
#include "material/StrainEnergy.h"
#include "mesh/TetMesh.h"

namespace tissuesim {

struct OrganPokeSetup {
  Eigen::Vector3d tipStart_m = Eigen::Vector3d::Zero();   ///< the probe's tip, outside the organ
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitY();  ///< unit, along the probe into the organ
  double probeRadius_m = 0.0025;
  Eigen::AlignedBox3d fixedBox_m;                            ///< the nodes in it are held
  std::vector<double> depths_m{0.001, 0.002, 0.003, 0.004};  ///< increasing, each > 0
  double depthStep_m = 0.0005;           ///< the largest increment between solves
  double pressureStiffness_Pa_m = 1e11;  ///< the probe's penalty per unit area
  /// Surface nodes within this distance of the entry point (at rest) can touch the probe (m).
  double contactReach_m = 0.015;
};

/// The FEM reference of the poke on `organ` (linear tets, positively oriented, its boundary the
/// organ's surface). The curve's force is along the probe's axis, at the setup's depths below
/// the entry point. @throws std::invalid_argument when the probe's axis misses the organ, no
/// node lies in the fixed box, or a depth does not increase. `onDepth` (when given) is called
/// with each depth (m) and its force (N) as it is reached: a reference takes minutes.
IndentationCurve pokeOrganFem(const StrainEnergy& energy, const TetMesh& organ,
                              const OrganPokeSetup& setup, double bulkModulus_Pa,
                              const std::function<void(double, double)>& onDepth = {});

}  // namespace tissuesim
