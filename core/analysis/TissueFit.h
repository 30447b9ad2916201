// SPDX-License-Identifier: Apache-2.0
#pragma once
// Fitting a tissue's seven constants to a uniaxial test (analysis/TensileTestData.h):
//
//   stage 1: mu, N, A1, A2 on the virgin loading points (the stretch above every earlier one),
//            where the stress is the continuum's P(lambda) alone (docs/model.md, Eqs. 13, 18);
//   stage 2: b and C on the other points (unloading, and reloading below an earlier peak),
//            where the softening (Eqs. 16-20) acts on the stage-1 curve.
//
// f is not fitted: W_T depends on it only through (1 - f) mu, f A1 and f A2, and the softening on
// mu / C, so every f fits a uniaxial test equally well with other moduli. It keeps the starting
// tissue's value (or the one given).
//
// Each stage is bounded nonlinear least squares on the stresses, by Eigen's Levenberg-Marquardt
// (unsupported/NonLinearOptimization, the MINPACK port, with a central-difference Jacobian): the
// problem has at most four unknowns and a few hundred residuals, and Eigen is already here;
// Ceres would bring a large dependency for what it does not need. Each residual is divided by
// |measured stress| + a fiftieth of the largest: a test's error grows with the load. Bounds by
// change of variables, so that every iterate is an admissible tissue: each positive parameter's
// logarithm is a logistic function of its unknown between the tissue file's admitted bounds
// (for N, the excess over N_min, the N whose chains lock just past the largest stretch
// measured, so every point stays inside the usable range). The problem is not convex (the
// network's locking and the fibre terms trade off), so each stage starts from several points,
// the starting tissue first, the rest spread log-uniformly over the values soft tissues take,
// and keeps the best.
//
// Uncertainties: the standard errors s sqrt(diag (J^T J)^-1), s^2 = SSR / (m - p), with J the
// residuals' Jacobian at the optimum, widened to half the spread of the starts that end as well
// as the best within the noise (an F test's margin). A parameter whose error is above half its
// value, or that lies along a direction J does not see, is reported as not identified by these
// data.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "analysis/UniaxialExperiment.h"
#include "material/TissueParameters.h"

namespace tissuesim {

/// The fitted constants, as the tissue file names them.
inline const std::vector<std::string>& fitParameterNames() {
  static const std::vector<std::string> names = {"mu_kpa", "N", "f",    "A1_kpa",
                                                 "A2_kpa", "b", "C_kpa"};
  return names;
}

struct TissueFitOptions {
  /// Everything the fit does not set (density, v_ij, n, the inverse Langevin, name), and the
  /// values of the parameters held fixed.
  TissueParameters base;
  /// Parameters held at base's value, by file name (fitParameterNames()); f always is.
  std::vector<std::string> fixed;
  int starts = 12;  ///< starting points per stage (>= 1)
  /// Called after each start of each stage: (done, total).
  std::function<void(int, int)> progress;
};

struct FittedParameter {
  std::string name;          ///< as the tissue file names it
  double value = 0.0;        ///< in the file's unit (kPa for moduli)
  double uncertainty = 0.0;  ///< standard error, same unit (0 when fixed)
  bool isFixed = false;
  bool isIdentified = true;
};

struct BranchFit {
  int cycle = 0;
  LoadPhase phase = LoadPhase::Loading;
  std::vector<double> model_Pa;  ///< the fitted model at the branch's points
  double rSquared = 0.0;
};

struct TissueFitResult {
  TissueParameters parameters;
  std::vector<FittedParameter> table;  ///< in fitParameterNames() order
  std::vector<BranchFit> branches;     ///< one per data branch
  std::vector<std::string> warnings;   ///< one line each: what the data could not decide
  std::vector<std::string> notes;      ///< one line each: what the fit chose not to fit
};

/// The model's engineering stresses (Pa) at every point of `data`, in the order measured, the
/// Mullins memory carried from point to point.
std::vector<std::vector<double>> modelStresses(const TissueParameters& parameters,
                                               const std::vector<CurveBranch>& data);

/// Sets the fitted parameter `name` (fitParameterNames()) of `parameters` to `value` in the
/// tissue file's unit (kPa for the moduli). @throws std::invalid_argument naming the fitted
/// parameters for any other name.
void setFitParameter(TissueParameters& parameters, const std::string& name, double value);

/// One line for a fitted tissue file's notes: R^2 per branch, then the notes and warnings.
std::string fitSummary(const TissueFitResult& result);

/// @throws std::invalid_argument with one line: fewer points than free parameters in a stage, an
/// unknown fixed name, no virgin loading points.
TissueFitResult fitTissue(const std::vector<CurveBranch>& data, const TissueFitOptions& options);

}  // namespace tissuesim
