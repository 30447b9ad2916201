// SPDX-License-Identifier: Apache-2.0
#include "analysis/TissueFit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include "analysis/GoodnessOfFit.h"
#include "material/StrainEnergy.h"
#include "material/StressSoftening.h"

namespace tissuesim {

namespace {

constexpr int kParameters = 7;
enum Index { kMu, kN, kF, kA1, kA2, kB, kC };
using Values = Eigen::Matrix<double, kParameters, 1>;  ///< SI: Pa for the moduli

bool isModulus(int i) { return i == kMu || i == kA1 || i == kA2 || i == kC; }

Values valuesOf(const TissueParameters& p) {
  Values v;
  v << p.mu_Pa, p.chainSegmentsN, p.fibreFraction, p.A1_Pa, p.A2_Pa, p.softeningB, p.softeningC_Pa;
  return v;
}

TissueParameters withValues(TissueParameters p, const Values& v) {
  p.mu_Pa = v[kMu];
  p.chainSegmentsN = v[kN];
  p.fibreFraction = v[kF];
  p.A1_Pa = v[kA1];
  p.A2_Pa = v[kA2];
  p.softeningB = v[kB];
  p.softeningC_Pa = v[kC];
  return p;
}

/// The index of a fitted parameter's file name. @throws std::invalid_argument for another name.
int indexOf(const std::string& name) {
  const std::vector<std::string>& names = fitParameterNames();
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end()) {
    std::string list;
    for (const std::string& each : names) list += (list.empty() ? "" : ", ") + each;
    throw std::invalid_argument("'" + name + "' is not a fitted parameter; expected one of " +
                                list);
  }
  return static_cast<int>(found - names.begin());
}

/// A measured point with its place in the test's history.
struct Point {
  double lambda;
  double stress_Pa;
  double peak;    ///< the largest stretch up to and including this point
  bool isVirgin;  ///< loading at a new largest stretch: the virgin curve alone
};

std::vector<Point> history(const std::vector<CurveBranch>& data) {
  std::vector<Point> points;
  double peak = 1.0;
  for (const CurveBranch& branch : data) {
    for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
      const double lambda = branch.stretch[i];
      const bool isVirgin = branch.phase == LoadPhase::Loading && lambda >= peak;
      peak = std::max(peak, lambda);
      points.push_back({lambda, branch.stress_Pa[i], peak, isVirgin});
    }
  }
  return points;
}

double modelAt(const StrainEnergy& energy, const StressSoftening& softening, const Point& point) {
  const double virgin = energy.stressAndSlope(point.lambda).value;
  return point.isVirgin ? virgin : softening.soften(virgin, point.lambda, point.peak);
}

/// The range a positive parameter moves in, as logarithms: within the tissue file's admitted
/// range (docs/tissue-file.md), for N the excess over its locking bound.
struct LogBounds {
  double low;
  double high;
};
LogBounds logBounds(int i) {
  if (i == kN) return {std::log(1e-9), std::log(0.99e8)};
  if (i == kB) return {std::log(1e-9), std::log(1e6)};
  return {std::log(1e-6), std::log(1e9)};  // moduli, Pa: up to 10^6 kPa
}

/// One stage: which parameters move, on which points, from which values.
struct Stage {
  std::vector<int> free;
  std::vector<Point> points;
  Values held;      ///< the values of every parameter that does not move
  double minimumN;  ///< N must stay above it (every point inside the usable range)
  TissueParameters base;
  /// Each residual is divided by |measured stress| + this floor (a fiftieth of the largest):
  /// a test's error grows with the load (a load cell's is a fraction of its reading), and
  /// unweighted, the few points near the peak would decide the whole fit.
  double floor_Pa;

  Values valuesAt(const Eigen::VectorXd& u) const {
    Values v = held;
    for (std::size_t k = 0; k < free.size(); ++k) {
      const int i = free[k];
      const double unit = 1.0 / (1.0 + std::exp(-u[static_cast<Eigen::Index>(k)]));
      if (i == kF) {
        v[i] = unit;
        continue;
      }
      const LogBounds bounds = logBounds(i);
      v[i] = (i == kN ? minimumN : 0.0) + std::exp(bounds.low + unit * (bounds.high - bounds.low));
    }
    return v;
  }

  Eigen::VectorXd unconstrained(const Values& v) const {
    Eigen::VectorXd u(static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) {
      const int i = free[k];
      double unit = v[i];
      if (i != kF) {
        const LogBounds bounds = logBounds(i);
        const double logValue = std::log(std::max(v[i] - (i == kN ? minimumN : 0.0), 1e-300));
        unit = (logValue - bounds.low) / (bounds.high - bounds.low);
      }
      unit = std::clamp(unit, 1e-9, 1.0 - 1e-9);
      u[static_cast<Eigen::Index>(k)] = std::log(unit / (1.0 - unit));
    }
    return u;
  }

  /// Residuals (model - measured) / scale at the values v; large where the model fails.
  void residuals(const Values& v, Eigen::VectorXd& r) const {
    const TissueParameters p = withValues(base, v);
    const StrainEnergy energy(p);
    const StressSoftening softening(p);
    for (std::size_t j = 0; j < points.size(); ++j) {
      const double model = modelAt(energy, softening, points[j]);
      r[static_cast<Eigen::Index>(j)] =
          std::isfinite(model)
              ? (model - points[j].stress_Pa) / (std::abs(points[j].stress_Pa) + floor_Pa)
              : 1e3;
    }
  }
};

/// Eigen's functor form for NumericalDiff and LevenbergMarquardt.
struct StageResiduals {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  const Stage* stage;
  int inputs() const { return static_cast<int>(stage->free.size()); }
  int values() const { return static_cast<int>(stage->points.size()); }
  int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& r) const {
    stage->residuals(stage->valuesAt(u), r);
    return 0;
  }
};

/// A start spread log-uniformly over the values soft tissues take (moduli 1 Pa to 100 MPa
/// depending on the term, N up to 100 above its bound, f uniformly in 0.02-0.98).
Values randomStart(std::mt19937& random, double minimumN) {
  const auto logUniform = [&](double low, double high) {
    return std::exp(std::uniform_real_distribution<double>(std::log(low), std::log(high))(random));
  };
  Values v;
  v << 1e3 * logUniform(1e-3, 1e2), minimumN + logUniform(1e-3, 1e2),
      std::uniform_real_distribution<double>(0.02, 0.98)(random), 1e3 * logUniform(1e-2, 1e4),
      1e3 * logUniform(1e-1, 1e5), logUniform(1e-2, 1e2), 1e3 * logUniform(1e-1, 1e3);
  return v;
}

/// A start's end: its values and its cost (the sum of squared scaled residuals).
struct StageSolution {
  Values values;
  double cost;
};

/// The best of several Levenberg-Marquardt runs, and every run's end in `ends`; `done` counts
/// the starts for progress.
Values solveStage(const Stage& stage, const Values& first, int starts, int& done, int total,
                  const std::function<void(int, int)>& progress, std::vector<StageSolution>& ends) {
  std::mt19937 random(20221407);
  Values best = first;
  double bestCost = std::numeric_limits<double>::infinity();
  Eigen::VectorXd r(static_cast<Eigen::Index>(stage.points.size()));
  for (int s = 0; s < starts; ++s) {
    Values start = s == 0 ? first : randomStart(random, stage.minimumN);
    for (int i = 0; i < kParameters; ++i) {
      if (std::find(stage.free.begin(), stage.free.end(), i) == stage.free.end())
        start[i] = stage.held[i];
    }
    Eigen::VectorXd u = stage.unconstrained(start);
    StageResiduals functor{&stage};
    Eigen::NumericalDiff<StageResiduals, Eigen::Central> numeric(functor);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<StageResiduals, Eigen::Central>> solver(numeric);
    solver.parameters.maxfev = 4000;
    solver.parameters.xtol = 1e-12;
    solver.parameters.ftol = 1e-14;
    solver.minimize(u);
    const Values v = stage.valuesAt(u);
    stage.residuals(v, r);
    const double cost = r.allFinite() ? r.squaredNorm() : std::numeric_limits<double>::infinity();
    ends.push_back({v, cost});
    if (cost < bestCost) {
      bestCost = cost;
      best = v;
    }
    if (progress) progress(++done, total);
  }
  return best;
}

/// Standard errors of the stage's free parameters at v (SI), and whether each is identified.
/// The problem is not convex: starts that end as well as the best one within the noise (an F
/// test's margin on the cost) but elsewhere widen the error to half their spread, where the
/// linearisation at one minimum cannot see the other.
void uncertainties(const Stage& stage, const Values& v, const std::vector<StageSolution>& ends,
                   std::vector<FittedParameter>& table) {
  const auto m = static_cast<Eigen::Index>(stage.points.size());
  const auto p = static_cast<Eigen::Index>(stage.free.size());
  if (p == 0) return;
  Eigen::VectorXd r(m), up(m), down(m);
  stage.residuals(v, r);
  // Sensitivities to relative changes: J diag(v), so the errors come out relative.
  Eigen::MatrixXd relative(m, p);
  for (Eigen::Index k = 0; k < p; ++k) {
    const int i = stage.free[static_cast<std::size_t>(k)];
    const double h = 1e-6;
    Values plus = v, minus = v;
    plus[i] *= 1.0 + h;
    minus[i] *= 1.0 - h;
    stage.residuals(plus, up);
    stage.residuals(minus, down);
    relative.col(k) = (up - down) / (2.0 * h);
  }
  const double dof = std::max<double>(1.0, static_cast<double>(m - p));
  const double variance = r.squaredNorm() / dof;
  // Directions the residuals do not see at all (singular values below 1e-7 of the largest):
  // every parameter with a real part in one is not identified, however well the curve fits.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(relative, Eigen::ComputeThinV);
  const Eigen::VectorXd& singular = svd.singularValues();
  std::vector<bool> isBlind(static_cast<std::size_t>(p), false);
  for (Eigen::Index j = 0; j < singular.size(); ++j) {
    if (singular[j] > 1e-7 * singular[0]) continue;
    for (Eigen::Index k = 0; k < p; ++k) {
      if (std::abs(svd.matrixV()(k, j)) > 0.1) isBlind[static_cast<std::size_t>(k)] = true;
    }
  }
  Eigen::MatrixXd normal = relative.transpose() * relative;
  normal.diagonal().array() += 1e-14 * std::max(normal.trace(), 1e-300);
  const Eigen::MatrixXd covariance = variance * normal.inverse();
  const double bestCost = r.squaredNorm();
  const double margin = 1.0 + 3.0 * static_cast<double>(p) / dof;  // about F(0.95; p, m - p)
  for (Eigen::Index k = 0; k < p; ++k) {
    const int i = stage.free[static_cast<std::size_t>(k)];
    FittedParameter& entry = table[static_cast<std::size_t>(i)];
    double relativeError = std::sqrt(std::max(covariance(k, k), 0.0));
    for (const StageSolution& end : ends) {
      if (!(end.cost <= margin * bestCost)) continue;
      relativeError = std::max(
          relativeError, 0.5 * std::abs(end.values[i] - v[i]) / std::max(std::abs(v[i]), 1e-300));
    }
    const bool isFinite = std::isfinite(relativeError) && !isBlind[static_cast<std::size_t>(k)];
    entry.uncertainty =
        isFinite ? relativeError * std::abs(entry.value) : std::numeric_limits<double>::infinity();
    entry.isIdentified = isFinite && relativeError <= 0.5;
  }
}

}  // namespace

std::vector<std::vector<double>> modelStresses(const TissueParameters& parameters,
                                               const std::vector<CurveBranch>& data) {
  const StrainEnergy energy(parameters);
  const StressSoftening softening(parameters);
  const std::vector<Point> points = history(data);
  std::vector<std::vector<double>> out;
  std::size_t j = 0;
  for (const CurveBranch& branch : data) {
    std::vector<double>& stresses = out.emplace_back();
    for (std::size_t i = 0; i < branch.stretch.size(); ++i)
      stresses.push_back(modelAt(energy, softening, points[j++]));
  }
  return out;
}

void setFitParameter(TissueParameters& parameters, const std::string& name, double value) {
  const int i = indexOf(name);
  Values values = valuesOf(parameters);
  values[i] = isModulus(i) ? 1000.0 * value : value;
  parameters = withValues(parameters, values);
}

std::string fitSummary(const TissueFitResult& result) {
  std::string text = "R^2 per branch:";
  for (const BranchFit& branch : result.branches) {
    char entry[96];
    std::snprintf(entry, sizeof entry, " cycle %d %s %.6f;", branch.cycle, phaseName(branch.phase),
                  branch.rSquared);
    text += entry;
  }
  for (const std::string& line : result.notes) text += " " + line + ".";
  for (const std::string& line : result.warnings) text += " " + line + ".";
  return text;
}

TissueFitResult fitTissue(const std::vector<CurveBranch>& data, const TissueFitOptions& options) {
  const std::vector<std::string>& names = fitParameterNames();
  std::vector<bool> isFixed(kParameters, false);
  for (const std::string& name : options.fixed)
    isFixed[static_cast<std::size_t>(indexOf(name))] = true;
  // W_T depends on f only through (1 - f) mu, f A1 and f A2, and the softening on mu / C: any f
  // is matched by other moduli, so a uniaxial test cannot tell it. It stays where it starts.
  const bool isFibreFractionChosen = isFixed[kF];
  isFixed[kF] = true;
  const std::vector<Point> points = history(data);
  double largestStretch = 1.0, largestStress = 0.0;
  for (const Point& point : points) {
    largestStretch = std::max(largestStretch, point.lambda);
    largestStress = std::max(largestStress, std::abs(point.stress_Pa));
  }
  // N whose usable range just reaches the largest stretch: lambda^3 - 3 k lambda + 2 = 0 with
  // k = N (1 - margin)^2 (StrainEnergy's usable range), and a little more.
  const double margin = StrainEnergy::kLockingMargin;
  const double minimumN = (largestStretch * largestStretch * largestStretch + 2.0) /
                          (3.0 * largestStretch) / ((1.0 - margin) * (1.0 - margin)) * (1.0 + 1e-6);

  Values values = valuesOf(options.base);
  if (!isFixed[kN] && !(values[kN] > minimumN)) values[kN] = 2.0 * minimumN;
  if (isFixed[kN] && !(values[kN] > minimumN)) {
    throw std::invalid_argument(
        "N held at " + std::to_string(values[kN]) + " locks before the largest stretch measured (" +
        std::to_string(largestStretch) + "; N must exceed " + std::to_string(minimumN) + ")");
  }

  const auto makeStage = [&](std::initializer_list<int> candidates, bool isVirgin) {
    Stage stage;
    for (const int i : candidates) {
      if (!isFixed[static_cast<std::size_t>(i)]) stage.free.push_back(i);
    }
    for (const Point& point : points) {
      if (point.isVirgin == isVirgin) stage.points.push_back(point);
    }
    stage.minimumN = minimumN;
    stage.base = options.base;
    stage.floor_Pa = largestStress > 0.0 ? largestStress / 50.0 : 1.0;
    return stage;
  };
  Stage loading = makeStage({kMu, kN, kF, kA1, kA2}, true);
  Stage unloading = makeStage({kB, kC}, false);
  if (loading.points.empty()) {
    throw std::invalid_argument(
        "no virgin loading points: the test must load to a new largest "
        "stretch at least once");
  }
  const auto checkCount = [](const Stage& stage, const char* what) {
    if (stage.points.size() < stage.free.size()) {
      throw std::invalid_argument(std::string(what) + ": " + std::to_string(stage.points.size()) +
                                  " points for " + std::to_string(stage.free.size()) +
                                  " free parameters; give more points or hold some fixed (--fix)");
    }
  };
  checkCount(loading, "the virgin loading branches");
  const bool fitsSoftening = !unloading.free.empty() && !unloading.points.empty();
  if (fitsSoftening) checkCount(unloading, "the unloading and reloading branches");

  const int starts = std::max(1, options.starts);
  const int total = starts * (fitsSoftening ? 2 : 1);
  int done = 0;
  std::vector<StageSolution> loadingEnds, unloadingEnds;
  loading.held = values;
  values = solveStage(loading, values, starts, done, total, options.progress, loadingEnds);
  if (fitsSoftening) {
    unloading.held = values;
    values = solveStage(unloading, values, starts, done, total, options.progress, unloadingEnds);
  }

  TissueFitResult result;
  result.parameters = withValues(options.base, values);
  for (int i = 0; i < kParameters; ++i) {
    FittedParameter entry;
    entry.name = names[static_cast<std::size_t>(i)];
    entry.value = isModulus(i) ? values[i] / 1000.0 : values[i];
    entry.isFixed = isFixed[static_cast<std::size_t>(i)];
    result.table.push_back(entry);
  }
  uncertainties(loading, values, loadingEnds, result.table);
  if (fitsSoftening) uncertainties(unloading, values, unloadingEnds, result.table);
  if (!isFibreFractionChosen) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "f held at %.4g: a uniaxial test sees only (1 - f) mu, f A1 and f A2, so f is "
                  "not fitted (--fix f=VALUE to choose it)",
                  options.base.fibreFraction);
    result.notes.emplace_back(line);
  }
  if (!fitsSoftening && !(isFixed[kB] && isFixed[kC])) {
    result.warnings.push_back(
        "no unloading or reloading points: b and C are not fitted (kept at "
        "the starting tissue's values)");
    for (const int i : {kB, kC}) result.table[static_cast<std::size_t>(i)].isIdentified = false;
  }
  for (const FittedParameter& entry : result.table) {
    if (entry.isFixed || entry.isIdentified) continue;
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s is not identified by these data (%.4g +- %.3g): the curve hardly depends on "
                  "it; hold it fixed (--fix %s=VALUE) if it is known",
                  entry.name.c_str(), entry.value, entry.uncertainty, entry.name.c_str());
    result.warnings.emplace_back(line);
  }

  const std::vector<std::vector<double>> model = modelStresses(result.parameters, data);
  for (std::size_t b = 0; b < data.size(); ++b) {
    BranchFit fit;
    fit.cycle = data[b].cycle;
    fit.phase = data[b].phase;
    fit.model_Pa = model[b];
    fit.rSquared = data[b].stress_Pa.size() >= 2
                       ? coefficientOfDetermination(data[b].stress_Pa, model[b])
                       : std::numeric_limits<double>::quiet_NaN();
    result.branches.push_back(std::move(fit));
  }
  return result;
}

}  // namespace tissuesim
