// SPDX-License-Identifier: Apache-2.0
#include "fem/HapticRateFem.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "forces/CapsuleGap.h"

namespace tissuesim {

HapticRateFem::HapticRateFem(FemModel& model, std::vector<char> isFixed,
                             std::vector<CapsulePenalty::Point> surface, double candidateMargin_m,
                             int newtonIterations, const FemExtraEnergy* support)
    : m_model(model),
      m_isFixed(std::move(isFixed)),
      m_surface(std::move(surface)),
      m_candidateMargin_m(candidateMargin_m),
      m_newtonIterations(newtonIterations),
      m_solver(kSolverTolerance_N, newtonIterations),
      m_x(model.mesh().nodes_m),
      m_settled(m_x) {
  if (m_isFixed.size() != static_cast<std::size_t>(m_x.size()))
    throw std::invalid_argument("HapticRateFem: one fixed flag per DOF");
  if (!(candidateMargin_m >= 0.0))
    throw std::invalid_argument("HapticRateFem: the candidates' margin must be >= 0");
  if (newtonIterations < 0)
    throw std::invalid_argument("HapticRateFem: an update's Newton iterations must be >= 0");
  for (const CapsulePenalty::Point& point : m_surface) {
    for (const int node : point.nodes) {
      if (node < 0 || node >= m_x.cols())
        throw std::invalid_argument("HapticRateFem: a surface point's node is not the mesh's");
    }
  }
  m_isInContact.assign(m_surface.size(), 0);
  m_model.setTangent(FemTangent::Definite);
  m_extraEnergy.terms = {&m_loads, support};
  m_model.setExtraEnergy(&m_extraEnergy);
}

HapticRateUpdate HapticRateFem::settle(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                                       double radius_m, CondensedCapsuleContact& next) {
  HapticRateUpdate report;
  m_loads.nodes.clear();
  m_loads.forces_N.resize(3, 0);
  m_lastLargestLoad_N = 0.0;
  m_stiffeningRate_per_m = 0.0;
  m_lastTip_m.reset();
  m_x = m_model.mesh().nodes_m;
  m_settled = m_x;
  FemSolveReport solved;
  // The solver's own tolerance, over as many iterations as the body takes to come to balance;
  // then an update's again.
  m_solver.setMaxIterations(kSettlingIterations);
  try {
    solved = m_solver.solve(m_model, m_x, m_isFixed);
  } catch (...) {
    m_solver.setMaxIterations(m_newtonIterations);
    throw;
  }
  m_solver.setMaxIterations(m_newtonIterations);
  report.residual_N = solved.residual_N;
  FemState state;
  // Linearised at the balance itself (the solve's last factorisation is an iterate behind).
  if (!solved.converged || !m_solver.factorize(m_model, m_x, m_isFixed, state)) {
    m_x = m_settled;
    report.isStepped = false;
    report.hasNext = false;
    return report;
  }
  m_settled = m_x;
  m_model.softenAt(m_x);  // the weight's own strain is the body's history from the start
  report.isStepped = true;
  linearize(tip_m, top_m, radius_m, next, report);
  m_settledTip_m = m_lastTip_m;
  return report;
}

HapticRateUpdate HapticRateFem::update(const CondensedCapsuleContact& inUse,
                                       const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                                       double radius_m, CondensedCapsuleContact& next) {
  if (inUse.hasBody()) inUse.bodyPositions(m_body);
  const HapticRateUpdate report = update(inUse.hasBody() ? &m_body : nullptr, inUse.candidates(),
                                         inUse.nodeForces(), tip_m, top_m, radius_m, next);
  if (!report.hasNext) next = inUse;  // the haptic loop keeps the contact it has
  return report;
}

void HapticRateFem::setHeldPoints(std::vector<int> points) {
  std::sort(points.begin(), points.end());
  m_heldPoints = std::move(points);
}

void HapticRateFem::restart() {
  m_x = m_settled;
  m_lastTip_m = m_settledTip_m;
  m_model.clearSoftening();
  m_model.softenAt(m_settled);
  std::fill(m_isInContact.begin(), m_isInContact.end(), char{0});
  m_lastLargestLoad_N = 0.0;
  m_lastLoadPattern.resize(0);
  m_stiffeningRate_per_m = 0.0;
}

HapticRateUpdate HapticRateFem::update(const Eigen::Matrix3Xd* body_m,
                                       const std::vector<int>& candidates,
                                       const Eigen::Matrix3Xd& candidateForces_N,
                                       const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                                       double radius_m, CondensedCapsuleContact& next) {
  if (candidateForces_N.cols() != static_cast<Eigen::Index>(candidates.size()))
    throw std::invalid_argument("HapticRateFem: one force per candidate");
  HapticRateUpdate report;
  // Where the contact in use has the body now; backtracked towards the last linearisation
  // where that would invert or lock an element.
  report.isStepped = true;
  if (body_m != nullptr) {
    if (body_m->cols() != m_x.cols())
      throw std::invalid_argument("HapticRateFem: the body's positions are not the mesh's");
    report.isStepped = false;
    double length = 1.0;
    for (int halving = 0; halving < 30 && !report.isStepped; ++halving, length *= 0.5) {
      m_candidate = m_x + length * (*body_m - m_x);
      report.isStepped = m_model.evaluate(m_candidate).isAdmissible;
    }
    if (report.isStepped) m_x = m_candidate;
  }
  // The softening's history where the update starts: its peaks raised there and held for this
  // update's Newton iterations and linearisation, each point below its peak on its softened
  // energy (FemModel::softenAt).
  m_model.softenAt(m_x);
  // Newton under the contact's forces now (as loads), from there; the solve's last
  // factorisation (one iterate behind where it ends) is the linearisation, or, where it took no
  // step, the Hessian factorised there.
  m_loads.nodes = candidates;
  m_loads.forces_N = candidateForces_N;
  FemSolveReport solved = m_solver.solve(m_model, m_x, m_isFixed);
  // Linearised far from its balance, the body's x_rest (below) is a long linear extrapolation of
  // a nonlinear body, and can fold it inside out: where the iterations leave it out of balance,
  // as many again, up to kRoundsUnderLoad rounds (the probe further than one round follows, or
  // points unloading from their peaks, where the paper's F falls steeply), and the contact in
  // use kept where that too falls short. A body with no load now or at the last update is not
  // behind the probe (it springs back, its softening redistributing the stress as it unloads):
  // it takes up to kRoundsWithNoLoad rounds, and no outrun is reported for it. It is iterated to
  // the solver's tolerance, not only to what the linearisation allows: its x_rest, a step taken
  // with the tangent where the iterations started, overshoots rest by the tissue's stiffening
  // (and by the softened curve's kink where points pass their peaks), and the next update, from
  // there, can throw it back as far: it would never settle.
  const double largestLoad_N =
      candidateForces_N.size() > 0 ? candidateForces_N.colwise().norm().maxCoeff() : 0.0;
  // A body the probe has just let go of still springs back from the last update's load.
  const double loadBorne_N = std::max(largestLoad_N, m_lastLargestLoad_N);
  m_lastLargestLoad_N = largestLoad_N;
  const double linearisable_N = kLinearisableResidual_N + kLinearisableLoadShare * loadBorne_N;
  const bool isFree = !(loadBorne_N > 0.0);
  const int rounds = isFree ? kRoundsWithNoLoad : kRoundsUnderLoad;
  const double wanted_N = isFree ? kSolverTolerance_N : linearisable_N;
  for (int round = 1; round < rounds && solved.residual_N > wanted_N; ++round)
    solved = m_solver.solve(m_model, m_x, m_isFixed);
  report.residual_N = solved.residual_N;
  if (solved.residual_N > linearisable_N) {
    report.hasNext = false;
    report.isOutOfBalance = true;
    return report;
  }
  FemState state;
  if (!m_solver.isFactorized() && !m_solver.factorize(m_model, m_x, m_isFixed, state)) {
    report.isStepped = false;
    report.hasNext = false;
    return report;
  }
  const int passed = linearize(tip_m, top_m, radius_m, next, report);
  report.isPassedThrough = passed > 0;
  return report;
}

HapticRateUpdate HapticRateFem::linearizeAt(const Eigen::Matrix3Xd& body_m,
                                            const Eigen::Vector3d& tip_m,
                                            const Eigen::Vector3d& top_m, double radius_m,
                                            CondensedCapsuleContact& next) {
  if (body_m.cols() != m_x.cols())
    throw std::invalid_argument("HapticRateFem: the body's positions are not the mesh's");
  HapticRateUpdate report;
  m_loads.nodes.clear();
  m_loads.forces_N.resize(3, 0);
  m_stiffeningRate_per_m = 0.0;  // the new material's own, found afresh
  m_lastTip_m.reset();
  FemState state;
  m_model.softenAt(body_m);
  if (!m_model.evaluate(body_m).isAdmissible ||
      !m_solver.factorize(m_model, body_m, m_isFixed, state)) {
    report.isStepped = false;
    report.hasNext = false;
    return report;
  }
  m_x = body_m;
  linearize(tip_m, top_m, radius_m, next, report);
  return report;
}

int HapticRateFem::linearize(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                             double radius_m, CondensedCapsuleContact& next,
                             HapticRateUpdate& report) {
  // The body's own out-of-balance force (the loads taken off), and where the linear body
  // settles with no load: x_rest = x - K^-1 dE/dx.
  Eigen::Matrix3Xd internal = m_solver.gradient();
  for (std::size_t l = 0; l < m_loads.nodes.size(); ++l)
    internal.col(m_loads.nodes[l]) += m_loads.forces_N.col(static_cast<Eigen::Index>(l));
  Eigen::MatrixXd correction = Eigen::Map<const Eigen::VectorXd>(internal.data(), internal.size());
  m_solver.solveFactorized(correction);

  // The candidates: the surface points near the probe where the body now is, and their nodes,
  // as far out as the probe's pace carries it while this contact is in use.
  const double travel_m = m_lastTip_m ? (tip_m - *m_lastTip_m).norm() : 0.0;
  m_lastTip_m = tip_m;
  const double margin_m = std::max(
      m_candidateMargin_m,
      std::min(m_candidateMargin_m + kCandidateTravelShare * travel_m, kLargestCandidateMargin_m));
  std::vector<int> points, nodes;
  int passed = 0;
  // A point the probe has passed through (kPassedThrough_m: inside a body reset to rest, or gone
  // past what the updates followed) is no contact: pushing it out would throw the body about.
  for (std::size_t p = 0; p < m_surface.size(); ++p) {
    const CapsulePenalty::Point& point = m_surface[p];
    const double gap_m = capsuleGap(point.position(m_x), tip_m, top_m, radius_m).gap_m;
    const bool wasInContact = m_isInContact[p] != 0;
    m_isInContact[p] = 0;
    const bool isHeld =
        !m_heldPoints.empty() &&
        std::binary_search(m_heldPoints.begin(), m_heldPoints.end(), static_cast<int>(p));
    if (gap_m < -kGoneThrough_m && wasInContact && !isHeld) ++passed;
    if (!isHeld && (gap_m > margin_m || gap_m < -kPassedThrough_m)) continue;
    m_isInContact[p] = 1;
    points.push_back(static_cast<int>(p));
    nodes.insert(nodes.end(), point.nodes.begin(), point.nodes.end());
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  const auto m = static_cast<Eigen::Index>(nodes.size());
  const auto pointCount = static_cast<Eigen::Index>(points.size());
  report.points = static_cast<int>(pointCount);
  report.candidates = static_cast<int>(m);
  next.setCandidates(nodes);
  next.bodyAtRest() = m_x - Eigen::Map<const Eigen::Matrix3Xd>(correction.data(), 3, m_x.cols());
  for (Eigen::Index j = 0; j < m; ++j)
    next.freePositions().col(j) = next.bodyAtRest().col(nodes[static_cast<std::size_t>(j)]);
  if (pointCount == 0) return passed;
  Eigen::MatrixXd& response = next.bodyResponse();
  response.setZero(m_x.size(), 3 * m);
  for (Eigen::Index j = 0; j < m; ++j) {
    for (int c = 0; c < 3; ++c) response(3 * nodes[static_cast<std::size_t>(j)] + c, 3 * j + c) = 1;
  }
  m_solver.solveFactorized(response);
  for (Eigen::Index j = 0; j < m; ++j)
    next.compliance().middleRows<3>(3 * j) =
        response.middleRows<3>(3 * nodes[static_cast<std::size_t>(j)]);
  Eigen::Matrix3Xi localNodes(3, pointCount);
  Eigen::Matrix3Xd weights(3, pointCount);
  Eigen::VectorXd stiffness_N_m(pointCount);
  for (Eigen::Index j = 0; j < pointCount; ++j) {
    const CapsulePenalty::Point& point =
        m_surface[static_cast<std::size_t>(points[static_cast<std::size_t>(j)])];
    for (int a = 0; a < 3; ++a) {
      localNodes(a, j) = static_cast<int>(
          std::lower_bound(nodes.begin(), nodes.end(), point.nodes[static_cast<std::size_t>(a)]) -
          nodes.begin());
    }
    weights.col(j) = point.weights;
    stiffness_N_m[j] = point.stiffness_N_m;
  }
  next.setPoints(localNodes, weights, stiffness_N_m);
  next.pointIds() = points;
  if (m_isStiffening) {
    Eigen::Vector3d load_N = Eigen::Vector3d::Zero();
    for (Eigen::Index l = 0; l < m_loads.forces_N.cols(); ++l) load_N += m_loads.forces_N.col(l);
    const double rate_per_N = stiffening(load_N.norm(), m_loadResponse);
    if (rate_per_N > 0.0) next.setStiffening(m_loadResponse, load_N.norm(), rate_per_N);
  }
  return passed;
}

double HapticRateFem::stiffening(double load_N, Eigen::Matrix3Xd& loadResponse) {
  if (load_N < kStiffeningLoad_N) {  // no press, or its end: the next one finds its own beta
    m_lastLoadPattern.resize(0);
    m_stiffeningRate_per_m = 0.0;
    return 0.0;
  }
  const bool isComparable = m_lastLoadPattern.size() == m_x.size() &&
                            std::abs(std::log(load_N / m_lastLoad_N)) >= kStiffeningLoadChange;
  // The loads' pattern now, and the last one's, each solved against K here.
  Eigen::MatrixXd& patterns = m_loadPatterns;
  patterns.setZero(m_x.size(), isComparable ? 2 : 1);
  for (std::size_t l = 0; l < m_loads.nodes.size(); ++l) {
    patterns.col(0).segment<3>(3 * m_loads.nodes[l]) =
        m_loads.forces_N.col(static_cast<Eigen::Index>(l));
  }
  for (Eigen::Index i = 0; i < patterns.rows(); ++i) {
    if (m_isFixed[static_cast<std::size_t>(i)] != 0) patterns(i, 0) = 0.0;
  }
  if (isComparable) patterns.col(1) = m_lastLoadPattern;
  m_loadResponses = patterns;
  m_solver.solveFactorized(m_loadResponses);
  loadResponse = Eigen::Map<const Eigen::Matrix3Xd>(m_loadResponses.col(0).data(), 3, m_x.cols());
  const double compliance_m_N = patterns.col(0).dot(m_loadResponses.col(0)) / (load_N * load_N);
  if (isComparable) {
    // The last pattern's stiffness when it was the load and now, against the load's change: the
    // body's own stiffening, the pattern's spreading left to the contact.
    const double now_m_N =
        patterns.col(1).dot(m_loadResponses.col(1)) / (m_lastLoad_N * m_lastLoad_N);
    if (now_m_N > 0.0 && m_lastLoadCompliance_m_N > 0.0) {
      // The chord's slope is the slope between the two loads; carried to this one as falling
      // with the load (k ~ ln F, the hanging liver's concave k(F); on the weightless liver,
      // whose k(F) is nearer straight, it errs towards the linear body).
      const double toHere = 0.5 * (load_N + m_lastLoad_N) / load_N;
      m_stiffeningRate_per_m = std::clamp(
          toHere * (1.0 / now_m_N - 1.0 / m_lastLoadCompliance_m_N) / (load_N - m_lastLoad_N), 0.0,
          kMaxStiffeningRate_per_m);
    }
  }
  if (isComparable || m_lastLoadPattern.size() != m_x.size()) {
    m_lastLoadPattern = patterns.col(0);
    m_lastLoad_N = load_N;
    m_lastLoadCompliance_m_N = compliance_m_N;
  }
  return m_stiffeningRate_per_m * compliance_m_N;
}

}  // namespace tissuesim
