// SPDX-License-Identifier: Apache-2.0
#pragma once
// The virtual uniaxial test of one material point: cyclic loading and unloading with rising
// amplitude, as in the paper's experiments (Section 6: lambda_max = 1.15, 1.23, 1.30), for any
// of the force laws of UniaxialModel.
//
// Cycle c loads from lambda = 1 to lambda_max[c], then unloads back to 1. The Mullins state
// carries over between cycles: reloading below an earlier lambda_max follows the softened
// curve, beyond it the virgin one (StressSoftening).

#include <span>
#include <stdexcept>
#include <vector>

#include "analysis/UniaxialModel.h"
#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/StressSoftening.h"
#include "springs/SpringForceLaw.h"

namespace tissuesim {

enum class LoadPhase { Loading, Unloading };
const char* phaseName(LoadPhase phase);

/// One branch of a cyclic test: stretches (dimensionless) and engineering stresses (Pa).
struct CurveBranch {
  int cycle = 0;  ///< 1-based
  LoadPhase phase = LoadPhase::Loading;
  std::vector<double> stretch;
  std::vector<double> stress_Pa;
};

struct UniaxialProtocol {
  std::vector<double> lambdaMax;  ///< one peak stretch per cycle, each > 1
  int pointsPerBranch = 100;      ///< >= 2, both ends included
};

/// The stretches of every branch (stresses left empty). Loading points are uniform in lambda;
/// unloading points cluster quadratically towards lambda_max, where the softening factor has a
/// vertical tangent (model.md).
std::vector<CurveBranch> protocolStretches(const UniaxialProtocol& protocol);

class UniaxialExperiment {
 public:
  UniaxialExperiment(const StrainEnergy& energy, const StiffnessTable& table);

  /// Checks a protocol against this tissue. @throws std::invalid_argument with one clear line:
  /// lambda_max <= 1, beyond the usable (locking) range, too few points.
  void validate(const UniaxialProtocol& protocol) const;

  /// Runs the protocol with one model. `smm` first runs `sedf` to fit its stiffness.
  std::vector<CurveBranch> run(UniaxialModel model, const UniaxialProtocol& protocol) const;

  /// The modulus E (Pa) of the linear law P = E (lambda - 1) fitted by least squares to the
  /// given reference branches (all points of all branches).
  static double fitLinearModulus(std::span<const CurveBranch> reference);
  /// The linear modulus a spring law needs (Pa): smm's, fitted to sedf over the paper's cycles
  /// (lambda_max 1.15, 1.23, 1.30); 0 for the laws that read the tables.
  static double springLawLinearModulus(SpringLaw law, const StrainEnergy& energy,
                                       const StiffnessTable& table);

 private:
  double virginStress(UniaxialModel model, double lambda, double linearModulus_Pa) const;

  const StrainEnergy& m_energy;
  const StiffnessTable& m_table;
  StressSoftening m_softening;
  StressSoftening m_roundedSoftening;  ///< with the FEM's points' onset
};

}  // namespace tissuesim
