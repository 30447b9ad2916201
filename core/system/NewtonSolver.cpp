// SPDX-License-Identifier: Apache-2.0
#include "system/NewtonSolver.h"

#include <cmath>
#include <limits>

#include "numerics/CholeskySolver.h"
#include "numerics/ConjugateGradientSolver.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind, double tolerance) {
  if (kind == LinearSolverKind::Cholesky) return std::make_unique<CholeskySolver>();
  return std::make_unique<ConjugateGradientSolver>(tolerance);
}

void NewtonSolver::prepare(MechanicalSystem& system) {
  if (m_preparedFor == &system) return;
  const Eigen::Index nodes = system.mesh().nodeCount();
  if (m_linearSolver->isDirect()) {
    m_operator.reset();
    m_matrix = std::make_unique<NodeBlockMatrix>(system.makeMatrix());
  } else {
    m_matrix.reset();
    m_operator = std::make_unique<SystemOperator>(system);
  }
  m_force.resize(3, nodes);
  m_r.resize(3, nodes);
  m_trialR.resize(3, nodes);
  m_trialX.resize(3, nodes);
  m_rhs.resize(3 * nodes);
  m_step.resize(3 * nodes);
  m_firstStep.setZero(3 * nodes);
  m_preparedFor = &system;
}

ForceReport NewtonSolver::forcesAndStiffness(const MechanicalSystem& system,
                                             const Eigen::Matrix3Xd& x, StiffnessSlot slot,
                                             bool isProjected) {
  ForcePass pass;
  pass.stiffness = slot;
  pass.isProjected = isProjected;
  return system.forces(x, m_force, pass);
}

ResidualNorms NewtonSolver::residual(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                                     const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                     Eigen::Matrix3Xd& r, ForceReport* report) {
  const ForceReport forces = system.forces(x, m_force);
  if (report != nullptr) *report = forces;
  return residualFromForce(system, x, xHat, inertiaWeight, r);
}

ResidualNorms NewtonSolver::residualFromForce(const MechanicalSystem& system,
                                              const Eigen::Matrix3Xd& x,
                                              const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                              Eigen::Matrix3Xd& r) {
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const std::vector<char>& fixed = system.fixedDofs();
  const auto pass = [&](int range, Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) {
      r.col(i) = inertiaWeight * mass[i] * (x.col(i) - xHat.col(i)) - m_force.col(i);
    }
    double* flat = r.data();
    double largest = 0.0;
    double squares = 0.0;
    for (Eigen::Index d = 3 * begin; d < 3 * end; ++d) {
      if (fixed[static_cast<std::size_t>(d)] != 0) flat[d] = 0.0;
      largest = std::max(largest, std::abs(flat[d]));
      squares += flat[d] * flat[d];
    }
    m_rangeLargest[static_cast<std::size_t>(range)] = largest;
    m_rangeSquares[static_cast<std::size_t>(range)] = squares;
  };
  forEachNodeRange(system.threadPool(), x.cols(), pass);
  ResidualNorms norms;
  for (int range = 0; range < kNodeRanges; ++range) {
    norms.largest_N = std::max(norms.largest_N, m_rangeLargest[static_cast<std::size_t>(range)]);
    norms.squared_N2 += m_rangeSquares[static_cast<std::size_t>(range)];
  }
  // A NaN or infinity anywhere makes the sum of squares non-finite (std::max may skip a NaN).
  if (!std::isfinite(norms.squared_N2)) norms.largest_N = std::numeric_limits<double>::quiet_NaN();
  return norms;
}

NewtonReport NewtonSolver::solve(MechanicalSystem& system, Eigen::Matrix3Xd& x,
                                 const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                 double regularization, int maxIterations, double tolerance_N) {
  prepare(system);
  NewtonReport report;
  const bool isDirect = m_linearSolver->isDirect();
  // Raises the shift tenfold from 1e-10 of K's largest diagonal entry; false once it reaches
  // 1e6 of it, where the step is a vanishing gradient step and nothing more can be gained.
  const auto raiseShift = [&](double& value) {
    const double scale = isDirect ? m_matrix->matrix().coeffs().cwiseAbs().maxCoeff()
                                  : m_operator->largestDiagonalEntry();
    value = value > 0.0 ? 10.0 * value : 1e-10 * scale;
    return value < 1e6 * scale;
  };
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const std::vector<char>& fixed = system.fixedDofs();
  ForkJoinPool* const pool = system.threadPool();
  m_linearSolver->setThreadPool(pool);
  const double rho = regularization;
  double shift = 0.0;  // Levenberg-Marquardt shift (N/m), relative to K's largest diagonal entry
  bool isExact = isDirect;  // a direct solver tells an indefinite exact Hessian: try it first
  // The first iteration's stiffness comes with the initial residual's forces, in one pass.
  bool isStiffnessCurrent = maxIterations > 0;
  ResidualNorms norms;  // of m_r
  if (isStiffnessCurrent) {
    report.forces = forcesAndStiffness(system, x, StiffnessSlot::Current, !isExact);
    norms = residualFromForce(system, x, xHat, inertiaWeight, m_r);
  } else {
    norms = residual(system, x, xHat, inertiaWeight, m_r, &report.forces);
  }
  report.residual_N = norms.largest_N;
  report.initialResidual_N = norms.largest_N;
  // Past the budget, only a residual above the extra iterations' threshold goes on.
  const auto isWithinBudget = [&] {
    return report.iterations < maxIterations ||
           (report.iterations < maxIterations + m_extraIterations &&
            report.residual_N > m_extraIterationResidual_N);
  };
  while (report.residual_N > tolerance_N && isWithinBudget() && std::isfinite(report.residual_N)) {
    ++report.iterations;
    if (!isStiffnessCurrent) forcesAndStiffness(system, x, StiffnessSlot::Current, !isExact);
    isStiffnessCurrent = false;  // the exact/projected choice below may change
    if (isDirect) {
      system.assembleStiffness(*m_matrix);
      for (Eigen::Index i = 0; i < x.cols(); ++i) {
        m_matrix->addToDiagonal(static_cast<int>(i), (inertiaWeight + rho) * mass[i] + shift);
      }
      m_matrix->applyFixedDofs(fixed);
    } else {
      m_operator->setDiagonal(inertiaWeight + rho, shift);
      m_operator->setFixedDofs(fixed);
    }
    const auto negate = [&](int, Eigen::Index begin, Eigen::Index end) {
      m_rhs.segment(3 * begin, 3 * (end - begin)) =
          -Eigen::Map<const Eigen::VectorXd>(m_r.col(begin).data(), 3 * (end - begin));
    };
    forEachNodeRange(pool, x.cols(), negate);

    // A time step's first Newton step is close to the last one's while the tissue moves
    // smoothly (both about dt^2 times the acceleration): an iterative solve starts from it.
    const bool isFirst = !isDirect && report.iterations == 1 && shift == 0.0;
    if (isFirst) m_step = m_firstStep;
    const BlockLinearOperator& a =
        isDirect ? static_cast<const BlockLinearOperator&>(*m_matrix) : *m_operator;
    const LinearSolveReport solved =
        m_linearSolver->solve(a, m_rhs, m_step, system.contacts.instrumentTerms(), isFirst);
    if (isFirst) m_firstStep = m_step;
    report.linearIterations += solved.iterations;
    const bool isSolved = solved.isSolved && m_step.allFinite();
    if (!isSolved && isExact) {
      isExact = false;  // indefinite: fall back to the PSD projection
      continue;
    }
    if (!isSolved) {
      // Singular even so: regularise more and try again.
      if (!raiseShift(shift)) break;
      isStiffnessCurrent = true;  // the same K, a larger shift
      continue;
    }

    // Backtracking on the residual's norm. When another iteration may follow, each trial also
    // keeps its stiffness (in the fields' trial slots, so the current one still scales the shift
    // below): the accepted trial's is then the next iteration's, with no second force pass.
    const bool isTrialStiffnessWanted = report.iterations < maxIterations;
    double stepLength = 1.0;
    bool isAccepted = false;
    ForceReport trialForces;
    ResidualNorms trialNorms;
    for (int halving = 0; halving < 12; ++halving) {
      const auto trial = [&](int, Eigen::Index begin, Eigen::Index end) {
        m_trialX.middleCols(begin, end - begin) =
            x.middleCols(begin, end - begin) +
            stepLength *
                Eigen::Map<const Eigen::Matrix3Xd>(m_step.data() + 3 * begin, 3, end - begin);
      };
      forEachNodeRange(pool, x.cols(), trial);
      if (isTrialStiffnessWanted) {
        trialForces = forcesAndStiffness(system, m_trialX, StiffnessSlot::Trial, !isDirect);
        trialNorms = residualFromForce(system, m_trialX, xHat, inertiaWeight, m_trialR);
      } else {
        trialNorms = residual(system, m_trialX, xHat, inertiaWeight, m_trialR, &trialForces);
      }
      if (std::isfinite(trialNorms.squared_N2) &&
          trialNorms.squared_N2 <= (1.0 - 1e-4 * stepLength) * norms.squared_N2) {
        isAccepted = true;
        break;
      }
      stepLength *= 0.5;
    }
    if (!isAccepted && isExact) {
      isExact = false;
      continue;
    }
    if (!isAccepted) {
      // No descent along the PSD-projected direction: lean towards gradient descent.
      if (!raiseShift(shift)) break;  // no descent even along the gradient: stagnated
      isStiffnessCurrent = true;      // the same K, a larger shift
      continue;
    }
    x.swap(m_trialX);
    m_r.swap(m_trialR);
    if (isTrialStiffnessWanted) {
      system.acceptTrialStiffness();
      isStiffnessCurrent = true;
    }
    report.forces = trialForces;
    norms = trialNorms;
    report.residual_N = norms.largest_N;
    shift *= 0.1;  // Levenberg-Marquardt: trust Newton again
    isExact = isDirect;
  }
  report.converged = report.residual_N <= tolerance_N;
  return report;
}

}  // namespace tissuesim
