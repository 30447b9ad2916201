// SPDX-License-Identifier: Apache-2.0
#pragma once
// The organ poke's continuum reference: the organ meshed conformally with its drawn surface (a
// tet mesh whose boundary is that surface, made offline by a mesher: assets/meshes/README.md),
// its tets made quadratic with one dilatation each (fem/FemModel.h, the indentation test's
// reference element), the nodes in the scene's fixed box held, weightless or under its weight on
// a tray (below); the probe (a capsule along the instrument's axis) lowered quasi-statically into
// the point where its axis first meets the surface, and the force along the axis on it at each
// depth below that point.
//
// The probe pushes the surface near that point by a penalty per unit area (CapsulePenalty, as
// the indentation test's FEM), on one of two samplings of the quadratic surface (the boundary's
// faces cut into four at their edges' midpoints): each quadratic node carrying its share of it
// (contactSpacing_m 0, the kept reference's), or points between three nodes about
// contactSpacing_m apart, each carrying its small triangle's area, so the probe meets the
// surface between the nodes as well. Every depth is a converged static equilibrium (Newton with
// the exact Hessian, CHOLMOD). Monotonic loading: no softening.

#include <functional>
#include <optional>
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
  /// Surface nodes (or pieces) within this distance of the entry point (at rest) can touch the
  /// probe (m).
  double contactReach_m = 0.015;
  /// 0: the penalty on each quadratic surface node; > 0: on points this far apart (m).
  double contactSpacing_m = 0.0;
  /// The body's weight (zero: weightless) at this density, and a tray under it (none: none).
  Eigen::Vector3d gravity_m_s2 = Eigen::Vector3d::Zero();
  double density_kg_m3 = 1060.0;
  struct Tray {
    Eigen::Vector3d up = Eigen::Vector3d::UnitY();  ///< out of the tray into the tissue
    double height_m = 0.0;                          ///< the plane up . y = height_m
    double stiffness_Pa_per_m = 1e7;                ///< its penalty per unit area
  };
  std::optional<Tray> tray;
};

/// The FEM reference of the poke on `organ` (linear tets, positively oriented, its boundary the
/// organ's surface). The curve's force is along the probe's axis, at the setup's depths below
/// the entry point (on the settled surface under gravity). @throws std::invalid_argument when the
/// probe's axis misses the organ, no node lies in the fixed box, a depth does not increase, or the
/// body does not come to balance under its weight. `onDepth` (when given) is called with each
/// depth (m) and its force (N) as it is reached: a reference takes minutes.
IndentationCurve pokeOrganFem(const StrainEnergy& energy, const TetMesh& organ,
                              const OrganPokeSetup& setup, double bulkModulus_Pa,
                              const std::function<void(double, double)>& onDepth = {});

/// The same poke through the FEM at its own rate and the probe's contact at the haptic rate
/// (fem/HapticRateFem.h): the probe driven at speed_m_s from startAbove_m above the entry point,
/// a contact solve each hapticStep_s; each FEM update takes the contact's forces at the step it
/// starts and is used from updateLatency_s later (0: its own wall time here, the FEM on a core
/// of its own), when the next one starts. The clock is the poke's, not the wall's.
struct HapticRateSettings {
  double speed_m_s = 0.002;
  double hapticStep_s = 0.001;
  double startAbove_m = 0.001;
  double updateLatency_s = 0.0;
  double candidateMargin_m = 0.001;        ///< HapticRateFem's
  int newtonIterations = 2;                ///< an update's
  bool isStiffeningBetweenUpdates = true;  ///< HapticRateFem::setStiffeningBetweenUpdates
};

struct HapticRatePoke {
  std::vector<double> force_N;  ///< along the axis, at each depth (between the steps either side)
  int nodes = 0;
  int elements = 0;
  long steps = 0;                    ///< haptic steps
  std::vector<double> stepTimes_ms;  ///< each haptic step's wall time
  long unconvergedSteps = 0;         ///< contact solves that did not settle
  long updates = 0;                  ///< FEM updates while the probe moved
  long unsteppedUpdates = 0;         ///< updates whose Newton iteration found no step
  double updating_s = 0.0;           ///< their wall time, all together
  double longestUpdate_s = 0.0;
  int maxCandidates = 0;  ///< the most surface nodes a contact held
  double seconds = 0.0;   ///< wall time, start-up included
};

/// The setup's contact sampled as it says (contactSpacing_m > 0 is the scheme's); weightless.
/// @throws std::invalid_argument as pokeOrganFem, or when a setting is out of range or the setup
/// has gravity or a tray.
HapticRatePoke pokeOrganHapticRate(const StrainEnergy& energy, const TetMesh& organ,
                                   const OrganPokeSetup& setup, double bulkModulus_Pa,
                                   const HapticRateSettings& settings);

}  // namespace tissuesim
