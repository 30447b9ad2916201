#include "integrators/NewtonSolver.h"

#include <cmath>
#include <limits>

#include "parallel/NodeRanges.h"

namespace tissuesim {

void NewtonSolver::prepare(const MechanicalSystem& system) {
  if (m_preparedFor == &system) return;
  const Eigen::Index nodes = system.mesh().nodeCount();
  m_isMatrixFree = m_kind == LinearSolverKind::ConjugateGradient;
  if (m_isMatrixFree) {
    m_matrix.reset();
    m_trialMatrix.reset();
    m_operator = std::make_unique<SpringSystemOperator>(system.mesh());
    m_linearization = system.makeLinearization();
    m_trialLinearization = system.makeLinearization();
  } else {
    m_operator.reset();
    m_matrix = std::make_unique<NodeBlockMatrix>(system.makeMatrix());
    m_trialMatrix = std::make_unique<NodeBlockMatrix>(system.makeMatrix());
  }
  m_isPatternAnalysed = false;
  m_force.resize(3, nodes);
  m_r.resize(3, nodes);
  m_trialR.resize(3, nodes);
  m_trialX.resize(3, nodes);
  m_rhs.resize(3 * nodes);
  m_step.resize(3 * nodes);
  m_firstStep.setZero(3 * nodes);
  m_contactTerms.reserve(256);  // PenaltyContactSet's reserve: a step's contacts, no allocation
  m_preparedFor = &system;
}

ForceReport NewtonSolver::forcesAndStiffness(const MechanicalSystem& system,
                                             const Eigen::Matrix3Xd& x, bool isTrial,
                                             bool isProjected) {
  if (m_isMatrixFree) {
    return system.forcesAndLinearization(
        x, m_force, isTrial ? m_trialLinearization : m_linearization, isProjected);
  }
  return system.forcesAndStiffness(x, m_force, isTrial ? *m_trialMatrix : *m_matrix, isProjected);
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
  forEachNodeRange(system.springs().threadPool(), x.cols(), pass);
  ResidualNorms norms;
  for (int range = 0; range < kNodeRanges; ++range) {
    norms.largest_N = std::max(norms.largest_N, m_rangeLargest[static_cast<std::size_t>(range)]);
    norms.squared_N2 += m_rangeSquares[static_cast<std::size_t>(range)];
  }
  // A NaN or infinity anywhere makes the sum of squares non-finite (std::max may skip a NaN).
  if (!std::isfinite(norms.squared_N2)) norms.largest_N = std::numeric_limits<double>::quiet_NaN();
  return norms;
}

NewtonReport NewtonSolver::solve(const MechanicalSystem& system, Eigen::Matrix3Xd& x,
                                 const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                 double regularization, int maxIterations, double tolerance_N) {
  prepare(system);
  NewtonReport report;
  // Raises the shift tenfold from 1e-10 of K's largest diagonal entry; false once it reaches
  // 1e6 of it, where the step is a vanishing gradient step and nothing more can be gained.
  const auto raiseShift = [&](double& value) {
    const double scale = m_isMatrixFree ? m_operator->largestDiagonalEntry()
                                        : m_matrix->matrix().coeffs().cwiseAbs().maxCoeff();
    value = value > 0.0 ? 10.0 * value : 1e-10 * scale;
    return value < 1e6 * scale;
  };
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const std::vector<char>& fixed = system.fixedDofs();
  const double rho = regularization;
  double shift = 0.0;  // Levenberg-Marquardt shift (N/m), relative to K's largest diagonal entry
  bool isExact = m_kind == LinearSolverKind::Cholesky;
  // The first iteration's stiffness comes with the initial residual's forces, in one pass.
  bool isMatrixCurrent = maxIterations > 0;
  ResidualNorms norms;  // of m_r
  if (isMatrixCurrent) {
    report.forces = forcesAndStiffness(system, x, /*isTrial=*/false, /*isProjected=*/!isExact);
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
    if (!isMatrixCurrent)
      forcesAndStiffness(system, x, /*isTrial=*/false, /*isProjected=*/!isExact);
    isMatrixCurrent = false;  // the shift and constraints below change it in place
    if (m_isMatrixFree) {
      m_operator->setSpringBlocks(m_linearization.springs);
      m_operator->setVolumeBlocks(system.volume() != nullptr ? &m_linearization.volume : nullptr);
      m_operator->setDiagonal(inertiaWeight + rho, shift);
      m_operator->setFixedDofs(fixed);
    } else {
      for (Eigen::Index i = 0; i < x.cols(); ++i) {
        m_matrix->addToDiagonal(static_cast<int>(i), (inertiaWeight + rho) * mass[i] + shift);
      }
      m_matrix->applyFixedDofs(fixed);
    }
    const auto negate = [&](int, Eigen::Index begin, Eigen::Index end) {
      m_rhs.segment(3 * begin, 3 * (end - begin)) =
          -Eigen::Map<const Eigen::VectorXd>(m_r.col(begin).data(), 3 * (end - begin));
    };
    forEachNodeRange(system.springs().threadPool(), x.cols(), negate);

    bool isSolved = false;
    if (m_kind == LinearSolverKind::Cholesky) {
      if (!m_isPatternAnalysed) {
        m_cholesky.analyzePattern(m_matrix->matrix());
        m_isPatternAnalysed = true;
      }
      m_cholesky.factorize(m_matrix->matrix());
      isSolved = m_cholesky.info() == Eigen::Success && (m_cholesky.vectorD().array() > 0.0).all();
      if (isSolved) m_step = m_cholesky.solve(m_rhs);
    } else {
      // Inexact Newton: the outer iteration tightens the rest.
      m_cg.setThreadPool(system.springs().threadPool());
      // The contacts at x: in the matrix already when assembled, the operator's terms when
      // matrix-free; and for the preconditioner to invert exactly.
      const std::size_t instrumentTerms = system.contacts.rankOneTerms(x, fixed, m_contactTerms);
      if (m_isMatrixFree) m_operator->setTerms(&m_contactTerms);
      const BlockLinearOperator& a =
          m_isMatrixFree ? static_cast<const BlockLinearOperator&>(*m_operator) : *m_matrix;
      // A time step's first Newton step is close to the last one's while the tissue moves
      // smoothly (both about dt^2 times the acceleration): CG starts from it.
      const bool isFirst = report.iterations == 1 && shift == 0.0;
      if (isFirst) m_step = m_firstStep;
      const ConjugateGradientReport cg =
          m_cg.solve(a, m_rhs, m_step, m_linearTolerance, static_cast<int>(3 * x.cols()),
                     std::span<const RankOneTerm>(m_contactTerms.data(), instrumentTerms), isFirst);
      if (isFirst) m_firstStep = m_step;
      report.linearIterations += cg.iterations;
      isSolved = cg.converged || cg.relativeResidual < std::max(1e-6, m_linearTolerance);
    }
    if ((!isSolved || !m_step.allFinite()) && isExact) {
      isExact = false;  // indefinite: fall back to the PSD projection
      continue;
    }
    if (!isSolved || !m_step.allFinite()) {
      // Singular even so: regularise more and try again.
      if (!raiseShift(shift)) break;
      continue;
    }

    // Backtracking on the residual's norm. When another iteration may follow, each trial also
    // assembles its stiffness (into the spare matrix, so the current one still scales the shift
    // below): the accepted trial's is then the next iteration's, with no second spring pass.
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
      forEachNodeRange(system.springs().threadPool(), x.cols(), trial);
      if (isTrialStiffnessWanted) {
        trialForces = forcesAndStiffness(system, m_trialX, /*isTrial=*/true,
                                         /*isProjected=*/m_kind != LinearSolverKind::Cholesky);
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
      continue;
    }
    x.swap(m_trialX);
    m_r.swap(m_trialR);
    if (isTrialStiffnessWanted) {
      if (m_isMatrixFree) {
        m_linearization.springs.swap(m_trialLinearization.springs);
        m_linearization.volume.swap(m_trialLinearization.volume);
      } else {
        m_matrix.swap(m_trialMatrix);
      }
      isMatrixCurrent = true;
    }
    report.forces = trialForces;
    norms = trialNorms;
    report.residual_N = norms.largest_N;
    shift *= 0.1;  // Levenberg-Marquardt: trust Newton again
    isExact = m_kind == LinearSolverKind::Cholesky;
  }
  report.converged = report.residual_N <= tolerance_N;
  return report;
}

}  // namespace tissuesim
