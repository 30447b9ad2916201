// SPDX-License-Identifier: Apache-2.0
#include "sim/SessionAssessment.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace tissuesim {
namespace {

void checkThresholds(const AssessmentThresholds& thresholds) {
  if (!(std::isfinite(thresholds.toolForce_N) && thresholds.toolForce_N > 0.0))
    throw std::invalid_argument("assessment: the force threshold must be a finite number > 0 N");
  if (!(std::isfinite(thresholds.damageStretch) && thresholds.damageStretch > 1.0))
    throw std::invalid_argument("assessment: the damage stretch must be a finite number > 1");
}

/// V_e = sum over the tets around spring e of V_t / 6 (SpringMesh's rule, unscaled).
Eigen::VectorXd springVolumes(const SpringMesh& mesh) {
  std::unordered_map<std::uint64_t, Eigen::Index> springOfEdge;
  springOfEdge.reserve(static_cast<std::size_t>(mesh.springCount()));
  const auto key = [](int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  };
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s)
    springOfEdge.emplace(key(mesh.springs(0, s), mesh.springs(1, s)), s);
  Eigen::VectorXd volume = Eigen::VectorXd::Zero(mesh.springCount());
  constexpr std::array<std::array<int, 2>, 6> kEdges{
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    for (const auto& [i, j] : kEdges) {
      const auto found = springOfEdge.find(key(mesh.tets(i, t), mesh.tets(j, t)));
      if (found != springOfEdge.end()) volume[found->second] += mesh.tetRestVolume_m3[t] / 6.0;
    }
  }
  return volume;
}

}  // namespace

SessionAssessment::SessionAssessment(const SpringMesh& mesh, const AssessmentThresholds& thresholds)
    : m_mesh(mesh),
      m_thresholds(thresholds),
      m_inverseRestLengthSquared_1_m2(mesh.restLength_m.array().square().inverse().matrix()),
      m_springVolume_m3(springVolumes(mesh)),
      m_peakStretchSquared(Eigen::VectorXd::Zero(mesh.springCount())),
      m_isDamaged(static_cast<std::size_t>(mesh.springCount()), 0),
      m_organVolume_m3(mesh.tetRestVolume_m3.sum()) {
  checkThresholds(thresholds);
}

void SessionAssessment::restart(const Eigen::Vector3d& toolTip_m) {
  m_lastTip_m = toolTip_m;
  m_peakStretchSquared.setZero();
  std::fill(m_isDamaged.begin(), m_isDamaged.end(), std::uint8_t{0});
  m_duration_s = 0.0;
  m_pathLength_m = 0.0;
  m_peakForce_N = 0.0;
  m_contactImpulse_Ns = 0.0;
  m_contactTime_s = 0.0;
  m_aboveThreshold_s = 0.0;
  m_largestStretchSquared = 1.0;
  m_damagedCount = 0;
  m_damagedVolume_m3 = 0.0;
}

void SessionAssessment::setDamageStretch(double damageStretch) {
  AssessmentThresholds thresholds = m_thresholds;
  thresholds.damageStretch = damageStretch;
  checkThresholds(thresholds);
  m_thresholds = thresholds;
  const double thresholdSquared = damageStretch * damageStretch;
  m_damagedCount = 0;
  m_damagedVolume_m3 = 0.0;
  for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) {
    const bool isDamaged = m_peakStretchSquared[s] >= thresholdSquared;
    m_isDamaged[static_cast<std::size_t>(s)] = isDamaged ? 1 : 0;
    if (isDamaged) {
      ++m_damagedCount;
      m_damagedVolume_m3 += m_springVolume_m3[s];
    }
  }
}

SessionAssessment::SpringPeaks SessionAssessment::springPeaks() const {
  SpringPeaks peaks;
  peaks.middles_m.resize(3, m_mesh.springCount());
  for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) peaks.middles_m.col(s) = restMiddle(s);
  peaks.peakStretchSquared = m_peakStretchSquared;
  return peaks;
}

void SessionAssessment::takeUpMesh(const SpringPeaks& peaks) {
  m_inverseRestLengthSquared_1_m2 = m_mesh.restLength_m.array().square().inverse().matrix();
  m_springVolume_m3 = springVolumes(m_mesh);
  m_organVolume_m3 = m_mesh.tetRestVolume_m3.sum();
  m_peakStretchSquared = Eigen::VectorXd::Zero(m_mesh.springCount());
  m_isDamaged.assign(static_cast<std::size_t>(m_mesh.springCount()), 0);
  if (peaks.peakStretchSquared.size() > 0 && peaks.peakStretchSquared.maxCoeff() > 0.0) {
    for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) {
      const Eigen::Vector3d middle = restMiddle(s);
      Eigen::Index nearest = 0;
      (peaks.middles_m.colwise() - middle).colwise().squaredNorm().minCoeff(&nearest);
      m_peakStretchSquared[s] = peaks.peakStretchSquared[nearest];
    }
  }
  setDamageStretch(m_thresholds.damageStretch);
}

double SessionAssessment::addStep(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& tip_m,
                                  double toolForce_N, double dt_s) {
  // The springs: each part its own range, its largest stretch and the volume it newly damaged.
  struct PartResult {
    double largestSquared = 0.0;
    long newlyDamaged = 0;
    double newlyDamagedVolume_m3 = 0.0;
  };
  std::array<PartResult, kParts> results{};
  const double thresholdSquared = m_thresholds.damageStretch * m_thresholds.damageStretch;
  runParts(m_pool, kParts, [&](int part) {
    PartResult result;
    const Eigen::Index end = partStart(part + 1);
    for (Eigen::Index s = partStart(part); s < end; ++s) {
      const double stretchSquared =
          (x.col(m_mesh.springs(1, s)) - x.col(m_mesh.springs(0, s))).squaredNorm() *
          m_inverseRestLengthSquared_1_m2[s];
      result.largestSquared = std::max(result.largestSquared, stretchSquared);
      if (stretchSquared <= m_peakStretchSquared[s]) continue;
      m_peakStretchSquared[s] = stretchSquared;
      std::uint8_t& isDamaged = m_isDamaged[static_cast<std::size_t>(s)];
      if (isDamaged == 0 && stretchSquared >= thresholdSquared) {
        isDamaged = 1;
        ++result.newlyDamaged;
        result.newlyDamagedVolume_m3 += m_springVolume_m3[s];
      }
    }
    results[static_cast<std::size_t>(part)] = result;
  });
  double stepLargestSquared = 0.0;
  for (const PartResult& result : results) {
    stepLargestSquared = std::max(stepLargestSquared, result.largestSquared);
    m_largestStretchSquared = std::max(m_largestStretchSquared, result.largestSquared);
    m_damagedCount += result.newlyDamaged;
    m_damagedVolume_m3 += result.newlyDamagedVolume_m3;
  }

  // The tool: its path over the step, its force.
  m_pathLength_m += (tip_m - m_lastTip_m).norm();
  m_lastTip_m = tip_m;
  m_peakForce_N = std::max(m_peakForce_N, toolForce_N);
  if (toolForce_N > 0.0) {
    m_contactTime_s += dt_s;
    m_contactImpulse_Ns += toolForce_N * dt_s;
  }
  if (toolForce_N > m_thresholds.toolForce_N) m_aboveThreshold_s += dt_s;
  m_duration_s += dt_s;
  return std::sqrt(stepLargestSquared);
}

AssessmentSummary SessionAssessment::summary() const {
  AssessmentSummary summary;
  summary.duration_s = m_duration_s;
  summary.toolPathLength_m = m_pathLength_m;
  summary.peakToolForce_N = m_peakForce_N;
  summary.meanContactForce_N = m_contactTime_s > 0.0 ? m_contactImpulse_Ns / m_contactTime_s : 0.0;
  summary.contactTime_s = m_contactTime_s;
  summary.aboveForceThreshold_s = m_aboveThreshold_s;
  summary.largestStretch = std::sqrt(m_largestStretchSquared);
  summary.damagedSpringCount = m_damagedCount;
  summary.damagedVolume_m3 = m_damagedVolume_m3;
  summary.organVolume_m3 = m_organVolume_m3;
  summary.thresholds = m_thresholds;
  return summary;
}

void damagedNodes(const SpringMesh& mesh, const std::vector<std::uint8_t>& damagedSprings,
                  Eigen::VectorXd& damage) {
  damage.setZero(mesh.nodeCount());
  const auto springs =
      std::min<Eigen::Index>(mesh.springCount(), static_cast<Eigen::Index>(damagedSprings.size()));
  for (Eigen::Index s = 0; s < springs; ++s) {
    if (damagedSprings[static_cast<std::size_t>(s)] == 0) continue;
    damage[mesh.springs(0, s)] = 1.0;
    damage[mesh.springs(1, s)] = 1.0;
  }
}

}  // namespace tissuesim
