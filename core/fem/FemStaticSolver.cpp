// SPDX-License-Identifier: Apache-2.0
#include "fem/FemStaticSolver.h"

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <Eigen/CholmodSupport>

#include "parallel/ForkJoinPool.h"

namespace tissuesim {
namespace {

/// Right-hand sides from which a solve is split between two threads: a body's response to its
/// contact's candidates (a hundred columns on a refined body) takes as long as the
/// factorisation on one thread, a Newton step's single column a small share of it.
constexpr Eigen::Index kColumnsForTwoThreads = 16;

}  // namespace

/// CHOLMOD's supernodal LL^T, its factor solved with from a second thread with that thread's own
/// workspace (CHOLMOD's solves only read the factor; its Common is the workspace).
class FemStaticSolver::SupernodalCholesky
    : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  /// columns overwritten by A^-1 columns, with the workspace given. @returns false where CHOLMOD
  /// could not (out of memory).
  bool solveColumns(Eigen::Ref<Eigen::MatrixXd> columns, cholmod_common& workspace) const {
    cholmod_dense rhs;
    rhs.nrow = static_cast<std::size_t>(columns.rows());
    rhs.ncol = static_cast<std::size_t>(columns.cols());
    rhs.nzmax = rhs.nrow * rhs.ncol;
    rhs.d = static_cast<std::size_t>(columns.outerStride());
    rhs.x = columns.data();
    rhs.z = nullptr;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* solved = cholmod_solve(CHOLMOD_A, m_cholmodFactor, &rhs, &workspace);
    if (solved == nullptr) return false;
    columns = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
        static_cast<const double*>(solved->x), columns.rows(), columns.cols(),
        Eigen::OuterStride<>(static_cast<Eigen::Index>(solved->d)));
    cholmod_free_dense(&solved, &workspace);
    return true;
  }
};

struct FemStaticSolver::Factorization {
  Factorization() {
    cholmod_start(&secondWorkspace);
    secondWorkspace.print = 0;
  }
  ~Factorization() { cholmod_finish(&secondWorkspace); }
  Factorization(const Factorization&) = delete;
  Factorization& operator=(const Factorization&) = delete;
  SupernodalCholesky cholesky;
  cholmod_common secondWorkspace;  ///< the second half's, for a solve split in two
  /// The halves' two threads, made at the first solve split in two (null before, or where no
  /// thread could be had: the caller's thread solves both).
  std::unique_ptr<ForkJoinPool> pool;
  bool isPoolTried = false;
};

FemStaticSolver::FemStaticSolver(double tolerance_N, int maxIterations)
    : m_tolerance_N(tolerance_N),
      m_maxIterations(maxIterations),
      m_factorization(std::make_unique<Factorization>()) {
  // An indefinite matrix is expected (the shift below handles it), not a message for stderr.
  m_factorization->cholesky.cholmod().print = 0;
  // Supernodes amalgamated more freely than CHOLMOD's default (4 / 16 / 48 columns, 0.8 / 0.1 /
  // 0.05 of explicit zeros): the quadratic tets' factors are small enough that dense BLAS on
  // bigger blocks outruns the few more flops (a quarter less time a factorisation on the
  // haptic-rate body, docs/performance-details.md).
  cholmod_common& common = m_factorization->cholesky.cholmod();
  common.nrelax[0] = 32;
  common.nrelax[1] = 128;
  common.nrelax[2] = 256;
  common.zrelax[0] = 0.9;
  common.zrelax[1] = 0.5;
  common.zrelax[2] = 0.3;
}

FemStaticSolver::~FemStaticSolver() = default;

namespace {

double largestFree(const Eigen::Matrix3Xd& gradient, const std::vector<char>& isFixed) {
  double largest = 0.0;
  const double* flat = gradient.data();
  for (Eigen::Index d = 0; d < gradient.size(); ++d) {
    if (isFixed[static_cast<std::size_t>(d)] == 0) largest = std::max(largest, std::abs(flat[d]));
  }
  return largest;
}

}  // namespace

bool FemStaticSolver::factorizeShifted(const std::vector<char>& isFixed, double& shift) {
  m_isFactorized = false;
  // The shifted copy only where a shift is needed: a definite Hessian is factorised as it is.
  Eigen::SparseMatrix<double> shifted;
  const double scale = m_hessian.diagonal().cwiseAbs().maxCoeff();
  for (;;) {
    if (shift > 0.0) {
      shifted = m_hessian;
      for (Eigen::Index d = 0; d < shifted.rows(); ++d) {
        if (isFixed[static_cast<std::size_t>(d)] == 0) shifted.coeffRef(d, d) += shift;
      }
    }
    m_factorization->cholesky.factorize(shift > 0.0 ? shifted : m_hessian);
    if (m_factorization->cholesky.info() == Eigen::Success) break;  // positive definite
    shift = shift > 0.0 ? 10.0 * shift : 1e-8 * scale;
    if (shift > 1e8 * scale) return false;
  }
  m_isFactorized = true;
  return true;
}

bool FemStaticSolver::factorize(const FemModel& model, const Eigen::Matrix3Xd& x,
                                const std::vector<char>& isFixed, FemState& state) {
  m_isFactorized = false;
  state = model.evaluate(x, m_gradient, m_hessian, isFixed, &m_assembly);
  if (!state.isAdmissible) return false;
  if (m_analysedFixed != isFixed) {
    m_factorization->cholesky.analyzePattern(m_hessian);
    m_analysedFixed = isFixed;
  }
  double shift = 0.0;
  return factorizeShifted(isFixed, shift);
}

void FemStaticSolver::solveFactorized(Eigen::MatrixXd& rhs) const {
  if (!m_isFactorized) throw std::logic_error("FemStaticSolver: nothing factorised to solve with");
  for (Eigen::Index d = 0; d < rhs.rows(); ++d) {
    if (m_analysedFixed[static_cast<std::size_t>(d)] != 0) rhs.row(d).setZero();
  }
  const Eigen::Index columns = rhs.cols();
  if (columns < kColumnsForTwoThreads) {
    rhs = m_factorization->cholesky.solve(rhs).eval();
  } else {
    // The columns' two halves as two parts on a pool of two threads, each half with its own
    // workspace whichever thread runs it.
    Factorization& factorization = *m_factorization;
    if (!factorization.isPoolTried) {
      factorization.isPoolTried = true;
      try {
        factorization.pool = std::make_unique<ForkJoinPool>(2);
      } catch (const std::system_error&) {  // no thread to be had: the caller's alone
      }
    }
    const Eigen::Index half = columns / 2;
    std::array<bool, 2> isSolved{false, false};
    runParts(factorization.pool.get(), 2, [&](int part) {
      isSolved[static_cast<std::size_t>(part)] =
          part == 0 ? factorization.cholesky.solveColumns(rhs.leftCols(half),
                                                          factorization.cholesky.cholmod())
                    : factorization.cholesky.solveColumns(rhs.rightCols(columns - half),
                                                          factorization.secondWorkspace);
    });
    if (!isSolved[0] || !isSolved[1])
      throw std::runtime_error("FemStaticSolver: CHOLMOD could not solve (out of memory)");
  }
  for (Eigen::Index d = 0; d < rhs.rows(); ++d) {
    if (m_analysedFixed[static_cast<std::size_t>(d)] != 0) rhs.row(d).setZero();
  }
}

FemSolveReport FemStaticSolver::solve(const FemModel& model, Eigen::Matrix3Xd& x,
                                      const std::vector<char>& isFixed) {
  FemSolveReport report;
  m_isFactorized = false;
  report.state = model.evaluate(x, m_gradient, m_hessian, isFixed, &m_assembly);
  if (!report.state.isAdmissible) return report;
  if (m_analysedFixed != isFixed) {  // the fixed DOFs shape the pattern
    m_factorization->cholesky.analyzePattern(m_hessian);
    m_analysedFixed = isFixed;
  }
  report.residual_N = largestFree(m_gradient, isFixed);
  double shift = 0.0;
  const Eigen::Index dofs = x.size();
  Eigen::VectorXd rhs(dofs), step(dofs);
  while (report.residual_N > m_tolerance_N && report.iterations < m_maxIterations) {
    ++report.iterations;
    for (Eigen::Index d = 0; d < dofs; ++d)
      rhs[d] = isFixed[static_cast<std::size_t>(d)] != 0 ? 0.0 : -m_gradient.data()[d];
    const double scale = m_hessian.diagonal().cwiseAbs().maxCoeff();
    if (!factorizeShifted(isFixed, shift)) return report;  // no definite matrix within reach
    step = m_factorization->cholesky.solve(rhs);
    // Backtracking on the energy while the step's predicted decrease stands above the energy's
    // round-off; below it (close to the solution) on the residual's size instead.
    const double slope = -step.dot(rhs);  // dE along the step (< 0)
    const bool isEnergyResolved = -slope > 1e-11 * std::abs(report.state.energy_J);
    // Each trial with its gradient: the accepted one's is the next iteration's, not evaluated
    // again.
    double length = 1.0;
    bool isAccepted = false;
    FemState trialState;
    for (int halving = 0; halving < 30 && !isAccepted; ++halving, length *= 0.5) {
      m_trial = x + length * Eigen::Map<const Eigen::Matrix3Xd>(step.data(), 3, x.cols());
      trialState = model.evaluate(m_trial, m_trialGradient);
      if (!trialState.isAdmissible) continue;
      isAccepted = isEnergyResolved
                       ? trialState.energy_J <= report.state.energy_J + 1e-4 * length * slope
                       : largestFree(m_trialGradient, isFixed) < report.residual_N;
    }
    if (!isAccepted) {
      shift = shift > 0.0 ? 10.0 * shift : 1e-8 * scale;
      if (shift > 1e8 * scale) return report;
      continue;
    }
    x = m_trial;
    std::swap(m_gradient, m_trialGradient);
    report.state = trialState;
    report.residual_N = largestFree(m_gradient, isFixed);
    // The Hessian only where another iteration will use it.
    if (report.residual_N > m_tolerance_N && report.iterations < m_maxIterations)
      report.state = model.evaluate(x, m_gradient, m_hessian, isFixed, &m_assembly);
    shift *= 0.1;
    if (shift < 1e-14 * scale) shift = 0.0;
  }
  report.converged = report.residual_N <= m_tolerance_N;
  return report;
}

}  // namespace tissuesim
