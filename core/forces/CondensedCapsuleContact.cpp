// SPDX-License-Identifier: Apache-2.0
#include "forces/CondensedCapsuleContact.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "forces/CapsuleGap.h"
#include "forces/SmoothedPenalty.h"

namespace tissuesim {
namespace {

/// Newton's iterations a solve may take (points slipping round a probe steered sideways creep:
/// through a softened body they still moved after 30), the force left on a candidate it settles
/// to (N: a hundredth of what a haptic device renders), and the step below which it stops (m:
/// under round-off for a body of millimetres).
constexpr int kMaxIterations = 60;
constexpr double kForceTolerance_N = 1e-5;
constexpr double kStepTolerance_m = 1e-12;
/// Gauss-Newton's iterations before the exact Hessian is tried: most solves, warm-started from
/// the last step's, settle within them.
constexpr int kGaussNewtonIterations = 3;
/// The stiffening's z = b (F - F_lin) is held to this range: S from 2.56 (unloaded from a
/// stiffened state) to 0.5 (twice the tangent's stiffness), past which a rate found over one
/// interval is not extrapolated.
constexpr double kSmallestStiffening = -0.9;
constexpr double kLargestStiffening = 2.51;

}  // namespace

void CondensedCapsuleContact::setCandidates(const std::vector<int>& nodes) {
  const auto m = static_cast<Eigen::Index>(nodes.size());
  m_nodes = nodes;
  m_compliance.setZero(3 * m, 3 * m);
  m_inverse.setZero(3 * m, 3 * m);
  m_free.setZero(3, m);
  m_positions.setZero(3, m);
  m_forces.setZero(3, m);
  m_pointNodes.resize(3, 0);
  m_pointWeights.resize(3, 0);
  m_pointStiffness_N_m.resize(0);
  m_pointIds.clear();
  m_heldNodes.resize(3, 0);
  m_heldWeights.resize(3, 0);
  m_heldTargets.resize(3, 0);
  m_u.setZero(3 * m);
  m_trialU.setZero(3 * m);
  m_gradient.setZero(3 * m);
  m_step.setZero(3 * m);
  m_work.setZero(3 * m);
  m_hessian.setZero(3 * m, 3 * m);
  m_turning.setZero(3 * m, 3 * m);
  m_exact.setZero(3 * m, 3 * m);
  m_bodyRest.resize(3, 0);
  m_bodyResponse.resize(0, 0);
  m_complianceLinear.resize(0, 0);
  m_inverseLinear.resize(0, 0);
  m_freeLinear.resize(3, 0);
  m_loadResponse.resize(3, 0);
  m_candidatesLoadResponse.resize(3, 0);
  m_linearisedLoad_N = 0.0;
  m_rate_per_N = 0.0;
  m_scale = 1.0;
}

void CondensedCapsuleContact::setStiffening(const Eigen::Matrix3Xd& loadResponse_m,
                                            double linearisedLoad_N, double rate_per_N) {
  if (!(rate_per_N >= 0.0) || !std::isfinite(rate_per_N))
    throw std::invalid_argument("CondensedCapsuleContact: the stiffening's rate must be >= 0");
  if (!(linearisedLoad_N >= 0.0) || !std::isfinite(linearisedLoad_N))
    throw std::invalid_argument("CondensedCapsuleContact: the linearised load must be >= 0");
  if (loadResponse_m.cols() != m_bodyRest.cols() || !loadResponse_m.allFinite())
    throw std::invalid_argument("CondensedCapsuleContact: one load response a body node");
  for (const int node : m_nodes) {
    if (node < 0 || node >= loadResponse_m.cols())
      throw std::invalid_argument("CondensedCapsuleContact: a candidate is not the body's node");
  }
  applyScale(1.0);
  m_complianceLinear = m_compliance;
  m_inverseLinear = m_inverse;
  m_freeLinear = m_free;
  m_loadResponse = loadResponse_m;
  m_candidatesLoadResponse.resize(3, static_cast<Eigen::Index>(m_nodes.size()));
  for (std::size_t j = 0; j < m_nodes.size(); ++j)
    m_candidatesLoadResponse.col(static_cast<Eigen::Index>(j)) = m_loadResponse.col(m_nodes[j]);
  m_linearisedLoad_N = linearisedLoad_N;
  m_rate_per_N = rate_per_N;
}

double CondensedCapsuleContact::secantScale(double load_N, double linearisedLoad_N,
                                            double rate_per_N) {
  // k(F) = k_lin (1 + z): the displacement from F_lin is ln(1 + z) / (b k_lin), the tangent's
  // (F - F_lin) / k_lin.
  if (rate_per_N <= 0.0) return 1.0;
  const double z = std::clamp(rate_per_N * (std::max(load_N, 0.0) - linearisedLoad_N),
                              kSmallestStiffening, kLargestStiffening);
  if (std::abs(z) < 1e-6) return 1.0 - 0.5 * z;
  return std::log1p(z) / z;
}

void CondensedCapsuleContact::applyScale(double scale) {
  if (scale == m_scale || m_inverseLinear.size() == 0) return;
  m_inverse = m_inverseLinear / scale;
  m_compliance = scale * m_complianceLinear;
  for (Eigen::Index j = 0; j < m_free.cols(); ++j) {
    const Eigen::Vector3d moved_m =
        m_freeLinear.col(j) + (1.0 - scale) * m_candidatesLoadResponse.col(j) - m_free.col(j);
    m_free.col(j) += moved_m;
    m_u.segment<3>(3 * j) -= moved_m;
  }
  m_scale = scale;
}

void CondensedCapsuleContact::setPoints(const Eigen::Matrix3Xi& localNodes,
                                        const Eigen::Matrix3Xd& weights,
                                        const Eigen::VectorXd& stiffness_N_m) {
  const auto m = static_cast<Eigen::Index>(m_nodes.size());
  if (weights.cols() != localNodes.cols() || stiffness_N_m.size() != localNodes.cols())
    throw std::invalid_argument("CondensedCapsuleContact: one weight column and stiffness a point");
  if (localNodes.size() > 0 && (localNodes.minCoeff() < 0 || localNodes.maxCoeff() >= m))
    throw std::invalid_argument("CondensedCapsuleContact: a point's node is not a candidate");
  for (Eigen::Index p = 0; p < stiffness_N_m.size(); ++p) {
    if (!(stiffness_N_m[p] > 0.0) || !std::isfinite(stiffness_N_m[p]))
      throw std::invalid_argument("CondensedCapsuleContact: a point's stiffness must be > 0");
  }
  const Eigen::LLT<Eigen::MatrixXd> cholesky(0.5 * (m_compliance + m_compliance.transpose()));
  if (cholesky.info() != Eigen::Success)
    throw std::invalid_argument("CondensedCapsuleContact: the compliance is not positive definite");
  m_inverse = cholesky.solve(Eigen::MatrixXd::Identity(3 * m, 3 * m));
  m_inverse = 0.5 * (m_inverse + m_inverse.transpose()).eval();
  m_pointNodes = localNodes;
  m_pointWeights = weights;
  m_pointStiffness_N_m = stiffness_N_m;
}

void CondensedCapsuleContact::setHeldPoints(const Eigen::Matrix3Xi& localNodes,
                                            const Eigen::Matrix3Xd& weights) {
  const auto m = static_cast<Eigen::Index>(m_nodes.size());
  if (weights.cols() != localNodes.cols())
    throw std::invalid_argument("CondensedCapsuleContact: one weight column a held point");
  if (localNodes.size() > 0 && (localNodes.minCoeff() < 0 || localNodes.maxCoeff() >= m))
    throw std::invalid_argument("CondensedCapsuleContact: a held point's node is not a candidate");
  m_heldNodes = localNodes;
  m_heldWeights = weights;
  m_heldTargets.resize(3, localNodes.cols());
  for (Eigen::Index h = 0; h < localNodes.cols(); ++h) m_heldTargets.col(h) = heldPosition(h);
}

Eigen::Vector3d CondensedCapsuleContact::between(const Eigen::Matrix3Xi& nodes,
                                                 const Eigen::Matrix3Xd& weights, Eigen::Index p,
                                                 const Eigen::VectorXd* u) const {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const int j = nodes(a, p);
    const Eigen::Vector3d at_m =
        u != nullptr ? Eigen::Vector3d(m_free.col(j) + u->segment<3>(3 * j)) : m_free.col(j);
    s += weights(a, p) * at_m;
  }
  return s;
}

Eigen::Vector3d CondensedCapsuleContact::pointPosition(Eigen::Index p) const {
  return between(m_pointNodes, m_pointWeights, p, &m_u);
}

Eigen::Vector3d CondensedCapsuleContact::heldFreePosition(Eigen::Index h) const {
  return between(m_heldNodes, m_heldWeights, h, nullptr);
}

Eigen::Vector3d CondensedCapsuleContact::heldPosition(Eigen::Index h) const {
  return between(m_heldNodes, m_heldWeights, h, &m_u);
}

double CondensedCapsuleContact::pointsEnergy(const Eigen::VectorXd& u, const Eigen::Vector3d& tip_m,
                                             const Eigen::Vector3d& top_m, double radius_m,
                                             Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian,
                                             Eigen::MatrixXd* turning, bool* touching) const {
  double energy = 0.0;
  if (touching != nullptr) *touching = m_heldNodes.cols() > 0;
  for (Eigen::Index h = 0; h < m_heldNodes.cols(); ++h) {
    const Eigen::Vector3d stretch_m =
        between(m_heldNodes, m_heldWeights, h, &u) - m_heldTargets.col(h);
    energy += 0.5 * heldStiffness_N_m * stretch_m.squaredNorm();
    if (gradient == nullptr) continue;
    const Eigen::Vector3d slope_N = heldStiffness_N_m * stretch_m;
    for (int a = 0; a < 3; ++a) {
      const int j = m_heldNodes(a, h);
      gradient->segment<3>(3 * j) += m_heldWeights(a, h) * slope_N;
      for (int b = 0; b < 3; ++b) {
        hessian->block<3, 3>(3 * j, 3 * m_heldNodes(b, h)).diagonal().array() +=
            m_heldWeights(a, h) * m_heldWeights(b, h) * heldStiffness_N_m;
      }
    }
  }
  for (Eigen::Index p = 0; p < m_pointNodes.cols(); ++p) {
    const CapsuleGap at =
        capsuleGap(between(m_pointNodes, m_pointWeights, p, &u), tip_m, top_m, radius_m);
    const PenaltyTerms terms = smoothedPenalty(at.gap_m);
    if (terms.curvature == 0.0) continue;
    if (touching != nullptr) *touching = true;
    const Eigen::Vector3d& normal = at.normal;
    const double k = m_pointStiffness_N_m[p];
    energy += k * terms.energy;
    if (gradient == nullptr) continue;
    // The Gauss-Newton part, as CapsulePenalty's, into `hessian`; the normal's turning, k e'
    // d2g/ds2 (negative semidefinite under penetration), into `turning`. With the turning the
    // Hessian can be indefinite where the probe presses hard against a soft body (a pressed
    // point would slide off the round probe); without it Newton converges only linearly along
    // the surface.
    const Eigen::Matrix3d block = (k * terms.curvature) * normal * normal.transpose();
    Eigen::Matrix3d turningBlock = Eigen::Matrix3d::Zero();
    if (turning != nullptr)
      turningBlock = (k * terms.slope) * capsuleGapCurvature(at, tip_m, top_m);
    for (int a = 0; a < 3; ++a) {
      const int j = m_pointNodes(a, p);
      gradient->segment<3>(3 * j) += (m_pointWeights(a, p) * k * terms.slope) * normal;
      for (int b = 0; b < 3; ++b) {
        const double w = m_pointWeights(a, p) * m_pointWeights(b, p);
        hessian->block<3, 3>(3 * j, 3 * m_pointNodes(b, p)) += w * block;
        if (turning != nullptr)
          turning->block<3, 3>(3 * j, 3 * m_pointNodes(b, p)) += w * turningBlock;
      }
    }
  }
  return energy;
}

Eigen::Vector3d CondensedCapsuleContact::solve(const Eigen::Vector3d& tip_m,
                                               const Eigen::Vector3d& top_m, double radius_m) {
  m_converged = false;
  m_iterations = 0;
  m_residual_N = 0.0;
  bool isResidualKnown = false;
  if (m_rate_per_N > 0.0)
    applyScale(secantScale(m_forces.rowwise().sum().norm(), m_linearisedLoad_N, m_rate_per_N));
  for (; m_iterations < kMaxIterations; ++m_iterations) {
    m_gradient.noalias() = m_inverse * m_u;
    m_hessian = m_inverse;
    // Past Gauss-Newton's first iterations, the exact Hessian where it is positive definite
    // (quadratic convergence along the surface too), else with a half or a quarter of the
    // normals' turning, else Gauss-Newton's.
    const bool isExactTried = m_iterations >= kGaussNewtonIterations;
    if (isExactTried) m_turning.setZero();
    bool isTouching = false;
    const double energy = 0.5 * m_u.dot(m_gradient) +
                          pointsEnergy(m_u, tip_m, top_m, radius_m, &m_gradient, &m_hessian,
                                       isExactTried ? &m_turning : nullptr, &isTouching);
    // Where nothing touches, settled means unloaded, exactly (Newton's next step takes it
    // there): within the tolerance, a force below it on each node would stay on for good (the
    // updates take it as a load, and the body as its state).
    const bool isWithinTolerance =
        isTouching ? m_gradient.cwiseAbs().maxCoeff() < kForceTolerance_N : m_u.isZero(0.0);
    if (m_gradient.size() == 0 || isWithinTolerance) {
      m_converged = true;
      isResidualKnown = true;
      m_residual_N = isTouching ? m_gradient.cwiseAbs().maxCoeff() : 0.0;
      break;
    }
    m_step = -m_gradient;
    // Touching nothing, Newton's step is exactly back to the unloaded candidates.
    bool isSolved = !isTouching;
    if (isSolved) m_step = -m_u;
    for (double share = 1.0; isExactTried && !isSolved && share > 0.2; share *= 0.5) {
      m_exact = m_hessian + share * m_turning;
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> exact(m_exact);  // in place: no allocation
      if (exact.info() == Eigen::Success) {
        exact.solveInPlace(m_step);
        isSolved = true;
      }
    }
    if (!isSolved) {
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> cholesky(m_hessian);
      if (cholesky.info() != Eigen::Success) break;
      cholesky.solveInPlace(m_step);
    }
    const double slope = m_step.dot(m_gradient);
    double length = 1.0;
    bool isAccepted = false;
    for (int halving = 0; halving < 30 && !isAccepted; ++halving, length *= 0.5) {
      m_trialU = m_u + length * m_step;
      m_work.noalias() = m_inverse * m_trialU;
      const double trial =
          0.5 * m_trialU.dot(m_work) +
          pointsEnergy(m_trialU, tip_m, top_m, radius_m, nullptr, nullptr, nullptr);
      isAccepted = trial <= energy + 1e-4 * length * slope;
      if (isAccepted) break;
    }
    if (!isAccepted) break;
    m_u = m_trialU;
    if (length * m_step.cwiseAbs().maxCoeff() < kStepTolerance_m) {
      m_converged = true;
      break;
    }
  }
  if (!isResidualKnown && m_u.size() > 0) {  // what is left where it stopped
    m_gradient.noalias() = m_inverse * m_u;
    m_hessian = m_inverse;
    pointsEnergy(m_u, tip_m, top_m, radius_m, &m_gradient, &m_hessian, nullptr);
    m_residual_N = m_gradient.cwiseAbs().maxCoeff();
  }
  m_work.noalias() = m_inverse * m_u;
  m_forces = Eigen::Map<const Eigen::Matrix3Xd>(m_work.data(), 3, m_forces.cols());
  m_positions = m_free + Eigen::Map<const Eigen::Matrix3Xd>(m_u.data(), 3, m_free.cols());
  return -m_forces.rowwise().sum();
}

void CondensedCapsuleContact::startFrom(const CondensedCapsuleContact& other) {
  m_work.setZero();
  for (std::size_t j = 0; j < m_nodes.size(); ++j) {
    const auto kept = std::find(other.m_nodes.begin(), other.m_nodes.end(), m_nodes[j]);
    if (kept == other.m_nodes.end()) continue;
    m_work.segment<3>(3 * static_cast<Eigen::Index>(j)) =
        other.m_forces.col(static_cast<Eigen::Index>(kept - other.m_nodes.begin()));
  }
  m_forces = Eigen::Map<const Eigen::Matrix3Xd>(m_work.data(), 3, m_forces.cols());
  if (m_rate_per_N > 0.0)
    applyScale(secantScale(m_forces.rowwise().sum().norm(), m_linearisedLoad_N, m_rate_per_N));
  m_u.noalias() = m_compliance * m_work;
}

void CondensedCapsuleContact::bodyPositions(Eigen::Matrix3Xd& x) const {
  x.resize(3, m_bodyRest.cols());
  firstBodyPositions(m_forces, x);
}

void CondensedCapsuleContact::firstBodyPositions(const Eigen::Matrix3Xd& forces_N,
                                                 Eigen::Matrix3Xd& x) const {
  const Eigen::Index n = x.cols();
  x = m_bodyRest.leftCols(n);
  if (!hasBody()) return;
  if (m_scale != 1.0) x += (1.0 - m_scale) * m_loadResponse.leftCols(n);
  Eigen::Map<Eigen::VectorXd>(x.data(), x.size()).noalias() +=
      m_scale * m_bodyResponse.topRows(3 * n) *
      Eigen::Map<const Eigen::VectorXd>(forces_N.data(), forces_N.size());
}

}  // namespace tissuesim
