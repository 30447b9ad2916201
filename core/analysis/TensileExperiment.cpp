// SPDX-License-Identifier: Apache-2.0
#include "analysis/TensileExperiment.h"

#include "analysis/UniaxialExperiment.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "fem/TetIsochoricForceField.h"
#include "integrators/ImplicitEulerSolver.h"
#include "integrators/QuasiNewtonSolver.h"
#include "integrators/SymplecticEulerSolver.h"
#include "mesh/BlockMesher.h"
#include "springs/SmallStrainCalibration.h"
#include "springs/SpringMesh.h"

namespace tissuesim {
namespace {

struct Specimen {
  SpringMesh mesh;
  std::vector<int> movingNodes;  ///< x = L face
  double length_m;
  double section_m2;
};

Specimen buildSpecimen(const TensileSpecimen& spec, double density) {
  Specimen out{buildSpringMesh(makeTensileSpecimenMesh(spec), density),
               {},
               spec.size_m.x(),
               spec.size_m.y() * spec.size_m.z()};
  return out;
}

/// Damped pseudo-time relaxation with a time integrator, to the same force tolerance.
NewtonReport relax(TimeIntegrator& integrator, MechanicalSystem& system, MechanicalState& state,
                   double dt, double tolerance, int maxSteps, Eigen::Matrix3Xd& scratch) {
  NewtonReport report;
  for (int stepIndex = 0; stepIndex < maxSteps; ++stepIndex) {
    const StepReport step = integrator.step(system, state, dt);
    report.iterations = stepIndex + 1;
    if (step.refused || !step.isFinite) break;
    report.forces = system.forces(state.x, scratch);
    report.residual_N = scratch.cwiseAbs().maxCoeff();
    if (report.residual_N <= tolerance) {
      report.converged = true;
      break;
    }
  }
  return report;
}

}  // namespace

TetMesh makeTensileSpecimenMesh(const TensileSpecimen& specimen) {
  if (specimen.cellsAcrossThickness < 1) {
    throw std::invalid_argument("--resolution must be at least 1 cell across the thickness");
  }
  const Eigen::Vector3d& size = specimen.size_m;
  const double h = size.z() / specimen.cellsAcrossThickness;
  const Eigen::Vector3i cells(std::max(1, static_cast<int>(std::lround(size.x() / h))),
                              std::max(1, static_cast<int>(std::lround(size.y() / h))),
                              specimen.cellsAcrossThickness);
  return makeBlockMesh(size, cells);
}

std::vector<char> tensileGripDofs(const Eigen::Matrix3Xd& rest, const Eigen::Vector3d& size,
                                  std::vector<int>& moving) {
  constexpr double kOnFace = 1e-12;
  std::vector<char> isFixed(static_cast<std::size_t>(rest.size()), 0);
  const auto fix = [&](Eigen::Index node, int axis) {
    isFixed[static_cast<std::size_t>(3 * node + axis)] = 1;
  };
  moving.clear();
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    const Eigen::Vector3d p = rest.col(i);
    if (std::abs(p.x()) < kOnFace) {
      fix(i, 0);
      if (p.y() < kOnFace && p.z() < kOnFace) {
        fix(i, 1);
        fix(i, 2);
      }
      if (std::abs(p.y() - size.y()) < kOnFace && p.z() < kOnFace) fix(i, 2);
      if (p.y() < kOnFace && std::abs(p.z() - size.z()) < kOnFace) fix(i, 1);
    }
    if (std::abs(p.x() - size.x()) < kOnFace) {
      fix(i, 0);
      moving.push_back(static_cast<int>(i));
    }
  }
  return isFixed;
}

TensileExperiment::TensileExperiment(const StrainEnergy& energy, const StiffnessTable& table,
                                     TensileSpecimen specimen)
    : m_energy(energy), m_table(table), m_specimen(specimen) {}

std::vector<CurveBranch> TensileExperiment::run(const TensileOptions& options,
                                                const UniaxialProtocol& protocol,
                                                TensilePointStats* stats) const {
  UniaxialExperiment(m_energy, m_table).validate(protocol);
  const TissueParameters& parameters = m_energy.parameters();
  const bool isTets = options.model == LatticeModel::IsochoricTets;
  if (isTets && !(options.bulkModulus_Pa > 0.0)) {
    throw std::invalid_argument(
        "the isochoric tets need the volume term for their volumetric part (a bulk modulus > 0)");
  }
  Specimen specimen = buildSpecimen(m_specimen, parameters.density_kg_m3);
  // With the tets, the springs stay for the mesh's structure and carry nothing (as a scene's
  // effects.model fem has them).
  specimen.mesh.volume_m3 *= isTets ? 0.0 : options.volumeScale;
  const SpringForceLaw law(options.law, m_table, parameters, options.linearModulus_Pa,
                           options.isSoftening && !isTets);
  SpringForceField springs(specimen.mesh, law);
  std::unique_ptr<VolumeForceField> volume;
  if (options.bulkModulus_Pa > 0.0) {
    volume = std::make_unique<VolumeForceField>(specimen.mesh, options.bulkModulus_Pa);
  }
  MechanicalSystem system(springs, volume.get());
  std::unique_ptr<TetIsochoricForceField> tets;
  if (isTets) {
    tets = std::make_unique<TetIsochoricForceField>(specimen.mesh.restPositions_m,
                                                    specimen.mesh.tets, m_energy);
    system.addField(*tets);
  }
  const std::vector<char> grips =
      tensileGripDofs(specimen.mesh.restPositions_m, m_specimen.size_m, specimen.movingNodes);
  for (std::size_t d = 0; d < grips.size(); ++d) {
    if (grips[d] != 0) system.fixDof(static_cast<int>(d / 3), static_cast<int>(d % 3));
  }

  IntegratorSettings settings;
  settings.massDamping_1_s = 0.0;
  settings.forceTolerance_N = options.forceTolerance_N;
  settings.maxIterations = options.maxIterationsPerPoint;
  std::unique_ptr<TimeIntegrator> integrator;
  if (options.integrator == "implicit") {
    integrator = std::make_unique<ImplicitEulerSolver>(settings, LinearSolverKind::Cholesky);
  } else if (options.integrator == "quasi-newton") {
    integrator = std::make_unique<QuasiNewtonSolver>(settings);
  } else if (options.integrator == "explicit") {
    // Dynamic relaxation: heavy mass damping, as many substeps as stability needs.
    settings.maxSubsteps = 1 << 20;
    settings.massDamping_1_s = 200.0;
    integrator = std::make_unique<SymplecticEulerSolver>(settings);
  } else if (options.integrator != "static") {
    throw std::invalid_argument("unknown --integrator '" + options.integrator +
                                "'; expected static, implicit, quasi-newton or explicit");
  }
  NewtonSolver newton(LinearSolverKind::Cholesky);

  MechanicalState state = system.restState();
  Eigen::Matrix3Xd scratch(3, specimen.mesh.nodeCount());
  Eigen::Matrix3Xd internal(3, specimen.mesh.nodeCount());
  double currentStretch = 1.0;
  double lastReaction_N = 0.0;
  TensilePointStats localStats;
  localStats.springs = static_cast<int>(specimen.mesh.springCount());
  localStats.tets = static_cast<int>(specimen.mesh.tets.cols());
  localStats.nodes = static_cast<int>(specimen.mesh.nodeCount());

  std::vector<CurveBranch> branches = protocolStretches(protocol);
  for (CurveBranch& branch : branches) {
    for (const double lambda : branch.stretch) {
      // Affine predictor along x from the last equilibrium, then the grip's new position.
      const double ratio = lambda / currentStretch;
      state.x.row(0) *= ratio;
      for (const int node : specimen.movingNodes) state.x(0, node) = lambda * specimen.length_m;
      state.v.setZero();
      currentStretch = lambda;

      // Relative to the grip force: near locking forces reach tens of N and the absolute floor
      // of round-off rises with them.
      const double tolerance = options.forceTolerance_N * std::max(1.0, std::abs(lastReaction_N));
      NewtonReport report;
      if (integrator) {
        // Pseudo-time. Implicit steps of 1 s are long against the specimen's slowest mode
        // (about 0.07 s for the liver strip), so each is nearly a static solve; explicit steps of
        // 1 ms relax through damping.
        const bool isExplicit = options.integrator == "explicit";
        report =
            relax(*integrator, system, state, isExplicit ? 1e-3 : 1.0, tolerance,
                  isExplicit ? 100 * options.maxIterationsPerPoint : options.maxIterationsPerPoint,
                  scratch);
      } else {
        report = newton.solve(system, state.x, state.x, 0.0, 0.0, options.maxIterationsPerPoint,
                              tolerance);
      }
      localStats.worstIterations = std::max(localStats.worstIterations, report.iterations);
      localStats.worstResidual_N = std::max(localStats.worstResidual_N, report.residual_N);
      localStats.worstRelativeResidual =
          std::max(localStats.worstRelativeResidual,
                   report.residual_N / tolerance * options.forceTolerance_N);
      localStats.unconvergedPoints += report.converged ? 0 : 1;
      if (!integrator) springs.commitStretchHistory(state.x);

      // Reaction at the moving grip: minus the springs' (and volume term's, and tets') pull on
      // its nodes.
      internal.setZero();
      springs.addForces(state.x, internal);
      if (volume) volume->addForces(state.x, internal, nullptr);
      if (tets) {
        ForceReport ignored;
        tets->addForces(state.x, internal, ForcePass{}, ignored);
      }
      double reaction = 0.0;
      for (const int node : specimen.movingNodes) reaction -= internal(0, node);
      branch.stress_Pa.push_back(reaction / specimen.section_m2);
      lastReaction_N = reaction;
    }
  }
  if (stats != nullptr) *stats = localStats;
  return branches;
}

double TensileExperiment::smallStrainCalibration(double initialShearModulus_Pa,
                                                 double bulkModulus_Pa) const {
  const TissueParameters& parameters = m_energy.parameters();
  const SpringMesh mesh =
      buildSpringMesh(makeTensileSpecimenMesh(m_specimen), parameters.density_kg_m3);
  UniaxialGrips grips;
  grips.isFixed = tensileGripDofs(mesh.restPositions_m, m_specimen.size_m, grips.movingNodes);
  grips.length_m = m_specimen.size_m.x();
  grips.section_m2 = m_specimen.size_m.y() * m_specimen.size_m.z();
  const SpringForceLaw law(SpringLaw::Eesm, m_table, parameters, 0.0, false);
  return smallStrainStiffnessScale(mesh, law, bulkModulus_Pa, grips, 3.0 * initialShearModulus_Pa);
}

double TensileExperiment::volumeTermCalibration(double initialShearModulus_Pa,
                                                double bulkModulus_Pa) const {
  const double springsOnly = smallStrainCalibration(initialShearModulus_Pa);
  if (!(bulkModulus_Pa > 0.0)) return springsOnly;
  // The paper's cycles, within the stretches this tissue admits (a tissue that locks early is
  // fitted over what it has).
  const double usable = 1.0 + 0.9 * (m_table.range().upper - 1.0);
  std::vector<double> ends;
  for (const double end : kVolumeFitRanges) {
    const double clipped = std::min(end, usable);
    if (clipped > 1.0 + 1e-6 && (ends.empty() || clipped > ends.back() + 1e-9))
      ends.push_back(clipped);
  }
  if (ends.empty()) return springsOnly;
  const UniaxialProtocol protocol{{ends.back()}, kVolumeFitPoints};
  const CurveBranch continuum =
      UniaxialExperiment(m_energy, m_table).run(UniaxialModel::Sedf, protocol).front();
  TensileOptions options;
  options.isSoftening = false;
  options.bulkModulus_Pa = bulkModulus_Pa;
  const auto loading = [&](double factor) {
    options.volumeScale = springsOnly * factor;
    return run(options, protocol).front().stress_Pa;
  };
  const std::vector<double> atOne = loading(1.0);
  const std::vector<double> atLow = loading(kVolumeFitLow);
  // Each range weighs as the R^2 of a cycle to its end does: its squared residuals over its own
  // sum of squares about the mean (a cycle to 1.15 counts as much as one to 1.3).
  std::vector<double> weight(continuum.stretch.size(), 0.0);
  for (const double end : ends) {
    double sum = 0.0;
    double sumOfSquares = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < continuum.stretch.size(); ++i) {
      if (continuum.stretch[i] > end + 1e-12) continue;
      sum += continuum.stress_Pa[i];
      sumOfSquares += continuum.stress_Pa[i] * continuum.stress_Pa[i];
      ++count;
    }
    const double spread = sumOfSquares - sum * sum / std::max(1, count);
    if (!(spread > 0.0)) continue;
    for (std::size_t i = 0; i < continuum.stretch.size(); ++i) {
      if (continuum.stretch[i] <= end + 1e-12) weight[i] += 1.0 / spread;
    }
  }
  // s(f) ~ s(1) + (f - 1) d, d = (s(1) - s(low)) / (1 - low): minimise the weighted
  // |s(f) - continuum|^2 in closed form.
  double numerator = 0.0;
  double denominator = 0.0;
  for (std::size_t i = 0; i < weight.size(); ++i) {
    const double slope = (atOne[i] - atLow[i]) / (1.0 - kVolumeFitLow);
    numerator += weight[i] * slope * (continuum.stress_Pa[i] - atOne[i]);
    denominator += weight[i] * slope * slope;
  }
  if (!(denominator > 0.0)) return springsOnly;
  return springsOnly * (1.0 + numerator / denominator);
}

}  // namespace tissuesim
