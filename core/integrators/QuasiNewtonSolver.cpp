// SPDX-License-Identifier: Apache-2.0
#include "integrators/QuasiNewtonSolver.h"

#include <algorithm>
#include <cmath>

#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

void QuasiNewtonSolver::prepare(const MechanicalSystem& system, double inertiaWeight,
                                const Eigen::Matrix3Xd& x) {
  const bool isSame = m_preparedFor == &system && m_preparedWeight == inertiaWeight &&
                      m_preparedRevision == system.constraintRevision();
  // A refactorisation that happens anyway takes the step's supports with it.
  const bool isRefoldWanted =
      !isSame || m_isRefreshWanted || supportChanges(system) > kMaxSupportChanges;
  if (!isRefoldWanted) return;
  const SpringMesh& mesh = system.mesh();
  const Eigen::Index dofs = 3 * mesh.nodeCount();
  if (!isSame) {
    m_h0 = std::make_unique<NodeBlockMatrix>(system.makeMatrix());
    m_h0Base = std::make_unique<NodeBlockMatrix>(*m_h0);
    m_isAnalysed = false;
  }
  if (!isSame || m_isRefreshWanted) {
    NodeBlockMatrix& base = *m_h0Base;
    base.setZero();
    if (m_isRefreshWanted) {
      // The fields' stiffness at x (the PSD projection), the contacts left to the Woodbury terms.
      m_force.resize(3, mesh.nodeCount());
      for (const ForceField* field : system.fields()) {
        if (field != &system.contacts)
          addStiffnessAt(*field, x, true, base, m_force, &system.fixedDofs());
      }
    } else {
      const double restSlope = system.springs().law().evaluate(1.0, 1.0).slope;  // P'(1) (Pa)
      for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
        const double k =
            mesh.volume_m3[s] * restSlope / (mesh.restLength_m[s] * mesh.restLength_m[s]);
        base.addEdgeStiffness(mesh.springs(0, s), mesh.springs(1, s),
                              k * Eigen::Matrix3d::Identity());
      }
      if (const VolumeForceField* volume = system.volume()) {
        // The volume term's stiffness at rest, (kappa / V0) g g^T per cell: kappa is tens of
        // times the springs' modulus, far more than L-BFGS's few pairs can learn.
        Eigen::Matrix3Xd restForces = Eigen::Matrix3Xd::Zero(3, mesh.nodeCount());
        addStiffnessAt(*volume, mesh.restPositions_m, true, base, restForces);
      }
    }
    m_isRefreshWanted = false;
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
      base.addToDiagonal(static_cast<int>(i), inertiaWeight * mesh.nodeMass_kg[i]);
    }
  }
  foldSupports(system);
  *m_h0 = *m_h0Base;
  addRankOneTerms(m_foldedTerms, *m_h0);
  m_h0->applyFixedDofs(system.fixedDofs());
  if (!m_isAnalysed) {
    m_initialHessian.analyzePattern(m_h0->matrix());
    m_isAnalysed = true;
  }
  m_initialHessian.factorize(m_h0->matrix());
  ++m_factorisationCount;
  if (isSame) return;

  const auto history = static_cast<Eigen::Index>(std::max(1, m_settings.historySize));
  for (Eigen::VectorXd* v : {&m_x, &m_xHat, &m_r, &m_newX, &m_newR, &m_q, &m_z}) v->resize(dofs);
  m_s.resize(dofs, history);
  m_y.resize(dofs, history);
  m_alpha.resize(history);
  m_rhoHistory.resize(history);
  m_force.resize(3, mesh.nodeCount());
  m_preparedFor = &system;
  m_preparedWeight = inertiaWeight;
  m_preparedRevision = system.constraintRevision();
}

int QuasiNewtonSolver::carriedIndex(const PenaltyContact& c) const {
  const auto point = static_cast<std::size_t>(c.supportPoint);
  if (!c.isSupport || c.supportPoint < 0 || point >= m_foldedSlot.size()) return -1;
  return m_foldedSlot[point];
}

int QuasiNewtonSolver::supportChanges(const MechanicalSystem& system) {
  std::fill(m_isFoldedPresent.begin(), m_isFoldedPresent.end(), 0);
  int changes = 0;
  for (const PenaltyContact& c : system.contacts.contacts()) {
    if (!c.isSupport) continue;
    const int index = carriedIndex(c);
    if (index >= 0) {
      m_isFoldedPresent[static_cast<std::size_t>(index)] = 1;
    } else {
      ++changes;
    }
  }
  for (const char present : m_isFoldedPresent) changes += present != 0 ? 0 : 1;
  return changes;
}

void QuasiNewtonSolver::foldSupports(const MechanicalSystem& system) {
  // Only a refactorising step comes here, and Eigen's factorisation allocates anyway.
  for (const int point : m_foldedPoints) m_foldedSlot[static_cast<std::size_t>(point)] = -1;
  m_foldedPoints.clear();
  m_foldedTerms.clear();
  for (const PenaltyContact& c : system.contacts.contacts()) {
    if (!c.isSupport || c.supportPoint < 0) continue;
    const auto point = static_cast<std::size_t>(c.supportPoint);
    if (point >= m_foldedSlot.size()) m_foldedSlot.resize(point + 1, -1);
    m_foldedSlot[point] = static_cast<int>(m_foldedTerms.size());
    m_foldedPoints.push_back(c.supportPoint);
    m_foldedTerms.push_back(
        pointTerm(c.nodes, c.weights, c.normal, c.stiffness_N_m, &system.fixedDofs()));
  }
  m_isFoldedPresent.assign(m_foldedTerms.size(), 1);
}

void QuasiNewtonSolver::prepareContacts(const MechanicalSystem& system) {
  // Every contact found, touching yet or not: one that comes into touch during the step but is
  // missing here is an explicit 10^4 N/m spring to L-BFGS, and with one or two iterations the
  // poke diverged. Counted as touching, a contact not yet reached only slows the node's approach
  // within the detection margin (half the tool's radius) while the iterations are few.
  const std::vector<PenaltyContact>& contacts = system.contacts.contacts();
  const std::vector<char>& fixed = system.fixedDofs();
  // The columns: each contact H0 does not carry (+), then each carried one the step lacks (-),
  // as supportChanges() or foldSupports() marked them.
  Eigen::Index count = 0;
  for (const PenaltyContact& c : contacts) count += carriedIndex(c) >= 0 ? 0 : 1;
  for (const char present : m_isFoldedPresent) count += present != 0 ? 0 : 1;
  // Resized only when the count changes (a new contact, not every step); then no allocation.
  if (m_contactU.cols() != count) {
    m_contactU.resize(m_x.size(), count);
    m_contactV.resize(m_x.size(), count);
    m_capacitanceMatrix.resize(count, count);
    m_columnSign.resize(count);
    m_projected.resize(count);
    m_contactScratch.resize(count);
  }
  m_contactU.setZero();
  Eigen::Index column = 0;
  // Column sqrt(k) u of term k u u^T (u zero on fixed DOFs), with its sign.
  const auto addColumn = [&](const RankOneTerm& term, double sign) {
    const double root = std::sqrt(term.stiffness_N_m);
    for (std::size_t k = 0; k < kMaxTermNodes; ++k) {
      for (int axis = 0; axis < 3; ++axis)
        m_contactU(3 * term.nodes[k] + axis, column) += root * term.blocks[k][axis];
    }
    m_columnSign[column] = sign;
    ++column;
  };
  for (const PenaltyContact& c : contacts) {
    if (carriedIndex(c) < 0)
      addColumn(pointTerm(c.nodes, c.weights, c.normal, c.stiffness_N_m, &fixed), 1.0);
  }
  for (std::size_t f = 0; f < m_foldedTerms.size(); ++f) {
    if (m_isFoldedPresent[f] == 0) addColumn(m_foldedTerms[f], -1.0);
  }
  if (count == 0) return;
  m_contactV = m_initialHessian.solve(m_contactU);
  m_capacitanceMatrix = m_columnSign.asDiagonal();
  m_capacitanceMatrix.noalias() += m_contactU.transpose() * m_contactV;
  m_capacitance.compute(m_capacitanceMatrix);
}

void QuasiNewtonSolver::applyInitialInverse(const Eigen::VectorXd& q, Eigen::VectorXd& z) {
  z = m_initialHessian.solve(q);
  if (m_contactU.cols() == 0) return;
  m_projected.noalias() = m_contactU.transpose() * z;
  m_contactScratch = m_capacitance.solve(m_projected);
  z.noalias() -= m_contactV * m_contactScratch;
}

double QuasiNewtonSolver::residual(const MechanicalSystem& system, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& r, ForceReport* report) {
  const Eigen::Map<const Eigen::Matrix3Xd> positions(x.data(), 3, system.mesh().nodeCount());
  const ForceReport forces = system.forces(positions, m_force);
  if (report != nullptr) *report = forces;
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const std::vector<char>& fixed = system.fixedDofs();
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    r[d] = fixed[static_cast<std::size_t>(d)] != 0
               ? 0.0
               : m_preparedWeight * mass[d / 3] * (x[d] - m_xHat[d]) - m_force.data()[d];
  }
  return r.cwiseAbs().maxCoeff();
}

StepReport QuasiNewtonSolver::step(MechanicalSystem& system, MechanicalState& state, double dt) {
  StepReport report;
  const double damping = 1.0 + m_settings.massDamping_1_s * dt;
  prepare(system, damping / (dt * dt), state.x);
  const Eigen::Index dofs = m_x.size();
  const Eigen::Map<const Eigen::VectorXd> x0(state.x.data(), dofs);
  const Eigen::Map<const Eigen::VectorXd> v0(state.v.data(), dofs);
  const std::vector<char>& fixed = system.fixedDofs();
  m_xHat = x0 + (dt / damping) * v0;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    m_x[d] = fixed[static_cast<std::size_t>(d)] != 0 ? x0[d] : m_xHat[d];
  }
  report.residual_N = residual(system, m_x, m_r, &report.forces);
  report.initialResidual_N = report.residual_N;
  prepareContacts(system);

  const Eigen::Index capacity = m_s.cols();
  Eigen::Index stored = 0;
  Eigen::Index newest = -1;
  // The iteration budget is the speed knob, but it is honoured only once the step has at least
  // halved the residual of its predictor x_hat (an inexact-Newton forcing term of 1/2). Where it
  // has not, H0, built from the springs' stiffness at rest, misses the tissue's stiffness (a
  // spring near locking is twenty times stiffer) and the step is explicit in that excess: with
  // one iteration that kept each step's residual below its start yet grew the start tenfold
  // over twenty steps, until the poke blew up (the test EveryIntegratorPokesTheLiverAlike). Such
  // a step iterates on, up to five times the budget, L-BFGS learning the missing stiffness.
  constexpr double kForcingTerm = 0.5;
  const double requiredResidual = kForcingTerm * report.residual_N;
  const int hardLimit = 5 * std::max(2, m_settings.maxIterations);
  // And, as Newton's steps do, a few more past the budget while the residual is one that would
  // count as an event (IntegratorSettings::extraIterations).
  const int extraLimit = m_settings.maxIterations + m_settings.extraIterations;
  while (report.residual_N > m_settings.forceTolerance_N && std::isfinite(report.residual_N) &&
         (report.iterations < m_settings.maxIterations ||
          (report.residual_N > requiredResidual && report.iterations < hardLimit) ||
          (report.residual_N > m_settings.extraIterationResidual_N &&
           report.iterations < extraLimit))) {
    ++report.iterations;
    // Two-loop recursion: z = H^-1 r with H0^-1 at the bottom.
    m_q = m_r;
    for (Eigen::Index k = 0; k < stored; ++k) {
      const Eigen::Index i = (newest - k + capacity) % capacity;
      m_alpha[i] = m_rhoHistory[i] * m_s.col(i).dot(m_q);
      m_q -= m_alpha[i] * m_y.col(i);
    }
    applyInitialInverse(m_q, m_z);
    for (Eigen::Index k = stored - 1; k >= 0; --k) {
      const Eigen::Index i = (newest - k + capacity) % capacity;
      const double beta = m_rhoHistory[i] * m_y.col(i).dot(m_z);
      m_z += (m_alpha[i] - beta) * m_s.col(i);
    }
    // Step -z, halved while the residual grows (a cheap safeguard, not a full line search).
    double length = 1.0;
    double newResidual = 0.0;
    ForceReport trialForces;
    for (int halving = 0; halving < 6; ++halving) {
      m_newX = m_x - length * m_z;
      newResidual = residual(system, m_newX, m_newR, &trialForces);
      if (std::isfinite(newResidual) && m_newR.squaredNorm() <= 4.0 * m_r.squaredNorm()) break;
      length *= 0.5;
    }
    const Eigen::Index slot = (newest + 1) % capacity;
    m_s.col(slot) = m_newX - m_x;
    m_y.col(slot) = m_newR - m_r;
    const double curvature = m_s.col(slot).dot(m_y.col(slot));
    if (curvature > 1e-300) {
      m_rhoHistory[slot] = 1.0 / curvature;
      newest = slot;
      stored = std::min(stored + 1, capacity);
    }
    m_x.swap(m_newX);
    m_r.swap(m_newR);
    report.residual_N = newResidual;
    report.forces = trialForces;
  }
  report.converged = report.residual_N <= m_settings.forceTolerance_N;
  // A step that could not halve its predictor's residual even past the budget: H0 misses the
  // stiffness the tissue has gained (or still carries what it has lost). The next step starts
  // from H0 refactorised at this step's end.
  m_isRefreshWanted = !report.converged && report.residual_N > requiredResidual;
  if (!m_x.allFinite() || !std::isfinite(report.residual_N)) {
    report.isFinite = false;
    report.reason = "non-finite force or position in a quasi-Newton step; state rolled back";
    return report;
  }
  Eigen::Map<Eigen::VectorXd> v(state.v.data(), dofs);
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (fixed[static_cast<std::size_t>(d)] == 0) v[d] = (m_x[d] - x0[d]) / dt;
  }
  Eigen::Map<Eigen::VectorXd>(state.x.data(), dofs) = m_x;
  system.springs().commitStretchHistory(state.x);
  return report;
}

}  // namespace tissuesim
