// SPDX-License-Identifier: Apache-2.0
#pragma once
// The indentation test: a block of tissue (default 60 x 60 x 30 mm), its bottom held, pressed at
// the centre of its top face by a rigid probe (a capsule of the simulator's instrument radius,
// axis vertical) to given depths below the top face, quasi-statically; the force on the probe at
// each depth. Through either model, to measure the spring network against the continuum:
//
// - the FEM reference (fem/FemModel.h) on a quarter of the block (symmetry planes x = 0 and
//   y = 0 through the probe's axis), on a rectilinear grid graded towards the probe: cells of
//   probeRadius / refinement there, growing by kGrowth a cell to at most kCoarsest;
// - the spring network with the simulator's settings (a spring law, V_e scaled by the
//   simulator's calibration, the volume term when asked for) on the whole block, a uniform Kuhn
//   lattice of a given cube edge, as `tissuesim mesh` makes for an organ.
//
// The probe pushes the top face by a penalty per unit area (CapsulePenalty). Every depth is a
// converged static equilibrium (Newton; the FEM with its exact Hessian); or, for the network, the
// poke is stepped at a scene's pace through a contact and an integrator as the simulator steps
// it. Both report the top face's displacement at sample points. Monotonic loading: softening
// plays no part.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/LatticeModel.h"
#include "forces/ContactProvider.h"
#include "integrators/TimeIntegrator.h"
#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "mesh/TetMesh.h"
#include "springs/SpringForceLaw.h"

namespace tissuesim {

struct IndentationSetup {
  Eigen::Vector3d size_m{0.06, 0.06, 0.03};
  double probeRadius_m = 0.0025;
  std::vector<double> depths_m{0.002, 0.004};  ///< increasing, each > 0
  double depthStep_m = 0.0005;                 ///< the largest increment between solves
  double pressureStiffness_Pa_m = 1e11;        ///< the probe's penalty per unit area
  /// Where the top face's displacement is compared at the last depth: offsets (m) in the top
  /// face from the probe's axis, in the quarter x, y >= 0 (the FEM's).
  std::vector<Eigen::Vector2d> surfaceSamples_m = defaultSurfaceSamples();

  /// Every 1 mm out to 15 mm from the axis, along x and along the diagonal.
  static std::vector<Eigen::Vector2d> defaultSurfaceSamples();
};

struct IndentationCurve {
  std::vector<double> force_N;  ///< on the probe, at each of the setup's depths
  int nodes = 0;
  int elements = 0;  ///< quadratic tets (FEM) or springs
  int unconvergedPoints = 0;
  double worstResidual_N = 0.0;  ///< the largest net force left on a free DOF at a solve's end
  double seconds = 0.0;
  /// A static FEM's Newton iterations over all its solves, and the wall time of those solves
  /// (each iteration assembles the Hessian, factorises it and line-searches).
  long newtonIterations = 0;
  double solving_s = 0.0;
  /// Those of them that brought the body to balance under its weight before the probe came
  /// down (the organ poke under gravity's), and how far that moved the entry point (m).
  long settlingIterations = 0;
  double entrySag_m = 0.0;
  /// The top face's displacement at the setup's surface samples, at the last depth (m).
  std::vector<Eigen::Vector3d> surfaceDisplacement_m;
  int failedSteps = 0;  ///< at a pace: steps refused or not finite (their state not advanced)
};

/// The network's knobs: its lattice's cube edge, its model, its spring law and its volume term.
struct IndentationNetwork {
  double cellEdge_m = 0.005;
  SpringLaw law = SpringLaw::Eesm;
  double bulkModulus_Pa = 0.0;  ///< 0: no volume term (the isochoric tets need one)
  /// The factor on V_e; 0: the simulator's for this volume term (simulatorStiffnessScale).
  double stiffnessScale = 0.0;
  LatticeModel model = LatticeModel::Springs;
};

/// The pace of a poke at a scene's speed: the probe descends at speed_m_s from the top face,
/// the network stepped by the named integrator (integrators/IntegratorChoice.h) at timeStep_s.
struct IndentationPace {
  std::string integrator = "implicit";
  IntegratorSettings settings;
  double speed_m_s = 0.04;
  double timeStep_s = 1e-3;
};

inline constexpr double kIndentationGrowth = 1.3;
inline constexpr double kIndentationCoarsest_m = 0.008;

/// The FEM reference at a refinement (>= 1: cells of probeRadius / refinement at the probe).
IndentationCurve indentFem(const StrainEnergy& energy, const IndentationSetup& setup,
                           int refinement, double bulkModulus_Pa);

/// The cube edge (m) of the block's lattice of about `targetSprings` springs (>= 100).
double indentationCellEdge(const IndentationSetup& setup, int targetSprings);

/// The spring network (cubes of network.cellEdge_m, at most kIndentationMaxCells a side),
/// each depth a static equilibrium.
IndentationCurve indentSprings(const StrainEnergy& energy, const StiffnessTable& table,
                               const IndentationSetup& setup, const IndentationNetwork& network);
inline constexpr int kIndentationMaxCells = 120;

/// The instrument's contact with the block's network, made for its tet mesh at rest (which
/// outlives it): the simulator's own (collision/CapsuleContact) where the caller has it.
using IndentationContactFactory =
    std::function<std::unique_ptr<ContactProvider>(const TetMesh& block)>;

/// The probe's penalty on the sampled top face (what the static solves use), as contacts frozen
/// for a step: each sampled point near the capsule held out of it along the line from the
/// axis, with the point's own stiffness. For tests of the paced poke without the collision layer.
IndentationContactFactory sampledTopFaceContact(const IndentationSetup& setup);

/// The same network poked at `pace`, as the simulator steps a scene: each step the contacts
/// found by `makeContact`'s provider at the step's start, then one integrator step. The force
/// on the probe as it passes each depth (interpolated between steps; where the integrator
/// applies contacts as impulses, their mean over the step), and the top face's displacement at
/// the step that reaches the last depth.
IndentationCurve indentSpringsAtPace(const StrainEnergy& energy, const StiffnessTable& table,
                                     const IndentationSetup& setup,
                                     const IndentationNetwork& network, const IndentationPace& pace,
                                     const IndentationContactFactory& makeContact);

}  // namespace tissuesim
