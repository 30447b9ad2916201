#pragma once
// The indentation test: a block of tissue (default 60 x 60 x 30 mm), its bottom held, pressed at
// the centre of its top face by a rigid probe (a capsule of the simulator's instrument radius,
// axis vertical) to given depths below the top face, quasi-statically; the force on the probe at
// each depth. Through either model, to measure the spring network against the continuum:
//
// - the FEM reference (fem/FemModel.h) on a quarter of the block (symmetry planes x = 0 and
//   y = 0 through the probe's axis), on a rectilinear grid graded towards the probe: cells of
//   probeRadius / refinement there, growing by kGrowth a cell to at most kCoarsest;
// - the spring network with the simulator's settings (the eesm law, V_e scaled by the lattice's
//   small-strain calibration, the volume term when asked for) on the whole block, a uniform Kuhn
//   lattice of about the asked number of springs, as `tissuesim mesh` makes for an organ.
//
// The probe pushes the top face's nodes by a penalty per unit area (CapsulePenalty). Every depth
// is a converged static equilibrium (Newton; the FEM with its exact Hessian). Monotonic loading:
// softening plays no part.

#include <vector>

#include <Eigen/Core>

#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"

namespace tissuesim {

struct IndentationSetup {
  Eigen::Vector3d size_m{0.06, 0.06, 0.03};
  double probeRadius_m = 0.0025;
  std::vector<double> depths_m{0.002, 0.004};  ///< increasing, each > 0
  double depthStep_m = 0.0005;                 ///< the largest increment between solves
  double pressureStiffness_Pa_m = 1e11;        ///< the probe's penalty per unit area
};

struct IndentationCurve {
  std::vector<double> force_N;  ///< on the probe, at each of the setup's depths
  int nodes = 0;
  int elements = 0;  ///< quadratic tets (FEM) or springs
  int unconvergedPoints = 0;
  double worstResidual_N = 0.0;  ///< the largest net force left on a free DOF at a solve's end
  double seconds = 0.0;
};

inline constexpr double kIndentationGrowth = 1.3;
inline constexpr double kIndentationCoarsest_m = 0.008;

/// The FEM reference at a refinement (>= 1: cells of probeRadius / refinement at the probe).
IndentationCurve indentFem(const StrainEnergy& energy, const IndentationSetup& setup,
                           int refinement, double bulkModulus_Pa);

/// The spring network of about `targetSprings` springs (>= 100), with the volume term of
/// `bulkModulus_Pa` (0: none).
IndentationCurve indentSprings(const StrainEnergy& energy, const StiffnessTable& table,
                               const IndentationSetup& setup, int targetSprings,
                               double bulkModulus_Pa);

}  // namespace tissuesim
