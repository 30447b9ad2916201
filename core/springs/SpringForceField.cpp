// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringForceField.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "numerics/CpuFeatures.h"
#include "numerics/NodeBlockMatrix.h"
#include "parallel/NodeRanges.h"
#include "springs/SpringStressBatch.h"

namespace tissuesim {
namespace {
/// Below this fraction of its rest length a spring has no usable direction.
constexpr double kCollapsedLengthFraction = 1e-9;
}  // namespace

SpringForceField::SpringForceField(const SpringMesh& mesh, const SpringForceLaw& law)
    : m_mesh(mesh),
      m_law(law),
      m_inverseRestLength(mesh.restLength_m.cwiseInverse()),
      m_areaOverLength(mesh.volume_m3.cwiseQuotient(mesh.restLength_m)),
      m_peaks(static_cast<std::size_t>(mesh.springCount()), law.peak(1.0)),
      m_lambdaMax(Eigen::VectorXd::Constant(mesh.springCount(), law.peak(1.0).lambdaMax)),
      m_slots{AxialBlocks(5, mesh.springCount()), AxialBlocks(5, mesh.springCount())} {
  // NaN: no pass has run yet, so no positions equal these.
  m_passPositions.setConstant(3, mesh.nodeCount(), std::numeric_limits<double>::quiet_NaN());
  m_passStretch.setZero(mesh.springCount());
  for (auto& f : m_partForces) f.resize(3, mesh.nodeCount());
  for (auto& k : m_partNodeStiffness) k.resize(mesh.nodeCount());
  for (int p = 0; p < kSpringParts; ++p) {
    NodeSpan& touched = m_partNodes[static_cast<std::size_t>(p)];
    touched = {mesh.nodeCount(), 0};
    for (Eigen::Index s = partStart(p); s < partStart(p + 1); ++s) {
      touched.begin =
          std::min<Eigen::Index>(touched.begin, std::min(mesh.springs(0, s), mesh.springs(1, s)));
      touched.end =
          std::max<Eigen::Index>(touched.end, std::max(mesh.springs(0, s), mesh.springs(1, s)) + 1);
    }
    touched.begin = std::min(touched.begin, touched.end);  // a part without springs: empty
  }
  m_isInert = mesh.volume_m3.isZero(0.0);
  setBatched(true);
}

SpringForceField::~SpringForceField() = default;

void SpringForceField::addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                 const ForcePass& pass, ForceReport& report) const {
  if (pass.nodeStiffness != nullptr) {
    report.springs = accumulate<false, true>(x, f, nullptr, pass.nodeStiffness, true);
  } else if (pass.stiffness == StiffnessSlot::None || m_isInert) {
    // An inert network's blocks stay the zeros they were made: only its stretches are wanted.
    report.springs = addForces(x, f);
  } else {
    const int slot = pass.stiffness == StiffnessSlot::Current ? m_current : m_current ^ 1;
    report.springs =
        addForcesAndStiffness(x, f, m_slots[static_cast<std::size_t>(slot)], pass.isProjected);
  }
}

void SpringForceField::prepareProducts(const PartBounds& bounds) {
  if (m_product && m_product->bounds() == bounds) return;
  m_product = std::make_unique<SpringStiffnessProduct>(m_mesh, bounds);
}

void SpringForceField::addStiffness(NodeBlockMatrix& matrix) const {
  if (m_isInert) return;
  // The matrix's edges are the springs, in order (MechanicalSystem::makeMatrix).
  matrix.addAxialEdgeStiffness(currentBlocks(), m_pool);
}

double SpringForceField::energy(const Eigen::Matrix3Xd& x) const {
  double energy = 0.0;
  for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) {
    const double lambda =
        (x.col(m_mesh.springs(1, s)) - x.col(m_mesh.springs(0, s))).norm() / m_mesh.restLength_m[s];
    // Simpson's rule on [1, lambda]: accurate for any of the three laws.
    constexpr int kPanels = 16;
    const double h = (lambda - 1.0) / kPanels;
    double sum = 0.0;
    for (int k = 0; k <= kPanels; ++k) {
      const double weight = (k == 0 || k == kPanels) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
      sum += weight * m_law.evaluate(1.0 + k * h, 1.0).stress;
    }
    energy += m_mesh.volume_m3[s] * sum * h / 3.0;
  }
  return energy;
}

bool SpringForceField::setBatched(bool isBatched) {
  m_isBatched = isBatched && hasAvxAndFma() && m_law.law() == SpringLaw::Eesm;
  return m_isBatched;
}

void SpringForceField::resetStretchHistory() {
  std::fill(m_peaks.begin(), m_peaks.end(), m_law.peak(1.0));
  m_lambdaMax.setConstant(m_law.peak(1.0).lambdaMax);
}

void SpringForceField::restoreStretchHistory(const std::vector<SofteningPeak>& peaks) {
  m_peaks = peaks;  // same size: no allocation
  for (std::size_t s = 0; s < m_peaks.size(); ++s)
    m_lambdaMax[static_cast<Eigen::Index>(s)] = m_peaks[s].lambdaMax;
}

template <bool withBlocks, bool withNodeStiffness>
SpringFieldReport SpringForceField::accumulate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                               AxialBlocks* blocks, Eigen::VectorXd* nodeStiffness,
                                               bool isProjected) const {
  std::array<SpringFieldReport, kSpringParts> reports;
  // Part 0 adds into the caller's arrays; every other part into its own buffer, cleared only
  // over the nodes its springs touch.
  auto part = [&](int p) {
    const Eigen::Index begin = partStart(p);
    const Eigen::Index end = partStart(p + 1);
    const auto range = [&](Eigen::Matrix3Xd& rangeForces, Eigen::VectorXd* rangeStiffness) {
      return m_isBatched ? accumulateRangeBatched<withBlocks, withNodeStiffness>(
                               begin, end, x, rangeForces, blocks, rangeStiffness, isProjected)
                         : accumulateRange<withBlocks, withNodeStiffness>(
                               begin, end, x, rangeForces, blocks, rangeStiffness, isProjected);
    };
    if (p == 0) {
      reports[0] = range(forces, nodeStiffness);
      return;
    }
    const auto q = static_cast<std::size_t>(p - 1);
    const NodeSpan touched = m_partNodes[static_cast<std::size_t>(p)];
    m_partForces[q].middleCols(touched.begin, touched.size()).setZero();
    if constexpr (withNodeStiffness)
      m_partNodeStiffness[q].segment(touched.begin, touched.size()).setZero();
    reports[static_cast<std::size_t>(p)] = range(m_partForces[q], &m_partNodeStiffness[q]);
  };
  runParts(m_pool, kSpringParts, part);
  // The parts' buffers added in part order, on node ranges (so the sums are bit-identical for
  // any thread count); a part adds only where its springs reached. Also the record of the
  // positions for the commit (the implicit solvers' passes; the explicit integrator's, with node
  // stiffness, do not record: its commit follows a position update, never a pass, and at 100k
  // springs the record cost it 10 %). What was recorded before stays valid: stretches are a
  // function of the positions alone.
  const auto reduce = [&](int, Eigen::Index rangeBegin, Eigen::Index rangeEnd) {
    for (int p = 1; p < kSpringParts; ++p) {
      const NodeSpan touched = m_partNodes[static_cast<std::size_t>(p)];
      const Eigen::Index begin = std::max(rangeBegin, touched.begin);
      const Eigen::Index end = std::min(rangeEnd, touched.end);
      if (begin >= end) continue;
      const auto q = static_cast<std::size_t>(p - 1);
      forces.middleCols(begin, end - begin) += m_partForces[q].middleCols(begin, end - begin);
      if constexpr (withNodeStiffness) {
        nodeStiffness->segment(begin, end - begin) +=
            m_partNodeStiffness[q].segment(begin, end - begin);
      }
    }
    if constexpr (!withNodeStiffness) {
      const Eigen::Index count = rangeEnd - rangeBegin;
      m_passPositions.middleCols(rangeBegin, count) = x.middleCols(rangeBegin, count);
    }
  };
  forEachNodeRange(m_pool, x.cols(), reduce);
  SpringFieldReport report = reports[0];
  for (int p = 1; p < kSpringParts; ++p) report.include(reports[static_cast<std::size_t>(p)]);
  return report;
}

template <bool withBlocks, bool withNodeStiffness>
SpringFieldReport SpringForceField::accumulateRange(Eigen::Index begin, Eigen::Index end,
                                                    const Eigen::Matrix3Xd& x,
                                                    Eigen::Matrix3Xd& forces, AxialBlocks* blocks,
                                                    Eigen::VectorXd* nodeStiffness,
                                                    bool isProjected) const {
  SpringFieldReport report;
  for (Eigen::Index s = begin; s < end; ++s) {
    const int a = m_mesh.springs(0, s);
    const int b = m_mesh.springs(1, s);
    const Eigen::Vector3d d = x.col(b) - x.col(a);
    const double length = d.norm();
    const double inverseRestLength = m_inverseRestLength[s];
    const double lambda = length * inverseRestLength;
    if constexpr (!withNodeStiffness) m_passStretch[s] = lambda;
    if (!(lambda > kCollapsedLengthFraction)) {
      ++report.collapsedCount;
      if constexpr (withBlocks) blocks->col(s).setZero();
      continue;
    }
    report.minStretch = std::min(report.minStretch, lambda);
    report.maxStretch = std::max(report.maxStretch, lambda);
    // The force-only pass asks the law for the stress alone (the same value to the bit).
    constexpr bool kWithSlope = withBlocks || withNodeStiffness;
    const SpringStress p = m_law.evaluate<kWithSlope>(lambda, m_peaks[static_cast<std::size_t>(s)]);
    report.beyondRangeCount += p.isBeyondRange ? 1 : 0;
    applyStress<withBlocks, withNodeStiffness>(s, a, b, d, length, p.stress, p.slope, forces,
                                               blocks, nodeStiffness, isProjected);
  }
  return report;
}

template <bool withBlocks, bool withNodeStiffness>
inline void SpringForceField::applyStress(Eigen::Index s, int a, int b, const Eigen::Vector3d& d,
                                          double length, double stress, double slope,
                                          Eigen::Matrix3Xd& forces, AxialBlocks* blocks,
                                          Eigen::VectorXd* nodeStiffness, bool isProjected) const {
  const double inverseRestLength = m_inverseRestLength[s];
  const double areaOverLength = m_areaOverLength[s];  // V_e / L0 (m^2)
  const double inverseLength = 1.0 / length;
  const Eigen::Vector3d n = d * inverseLength;
  const Eigen::Vector3d f = (areaOverLength * stress) * n;
  forces.col(a) += f;
  forces.col(b) -= f;
  if constexpr (withBlocks || withNodeStiffness) {
    double axial = areaOverLength * slope * inverseRestLength;
    double lateral = areaOverLength * stress * inverseLength;
    if (isProjected) {
      axial = std::max(0.0, axial);
      lateral = std::max(0.0, lateral);
    }
    if constexpr (withBlocks) {
      double* const k = blocks->col(s).data();
      k[0] = n[0];
      k[1] = n[1];
      k[2] = n[2];
      k[3] = axial - lateral;
      k[4] = lateral;
    }
    if constexpr (withNodeStiffness) {
      // ||K_e||_2 of the unprojected block: the larger of its two eigenvalues' magnitudes.
      const double norm = std::max(std::abs(areaOverLength * slope * inverseRestLength),
                                   std::abs(areaOverLength * stress * inverseLength));
      (*nodeStiffness)[a] += norm;
      (*nodeStiffness)[b] += norm;
    }
  }
}

template <bool withBlocks, bool withNodeStiffness>
#if defined(__x86_64__)
__attribute__((target("avx,fma")))
#endif
SpringFieldReport
SpringForceField::accumulateRangeBatched(Eigen::Index begin, Eigen::Index end,
                                         const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                         AxialBlocks* blocks, Eigen::VectorXd* nodeStiffness,
                                         bool isProjected) const {
#if defined(__x86_64__)
  constexpr bool kWithSlope = withBlocks || withNodeStiffness;
  const SpringStressBatchCoefficients coefficients(m_law);
  const StretchRange range = m_law.range();
  SpringFieldReport report;
  // Groups of four: the geometry per spring (the same expressions as the scalar pass, so the
  // same stretches to the bit), the law for the four at once, then each spring's force. The
  // next group's geometry is taken before this group's law: its square roots and loads then
  // run while the law waits on its own chain (stretch, spline cell, table load, exp).
  struct Group {
    std::array<int, 4> a{}, b{};
    std::array<Eigen::Vector3d, 4> d;
    alignas(32) std::array<double, 4> length{}, lambda{};
    bool isInside = true;
  };
  const auto measure = [&](Eigen::Index first, Group& group) {
    group.isInside = true;
    for (std::size_t k = 0; k < 4; ++k) {
      const Eigen::Index spring = first + static_cast<Eigen::Index>(k);
      group.a[k] = m_mesh.springs(0, spring);
      group.b[k] = m_mesh.springs(1, spring);
      group.d[k] = x.col(group.b[k]) - x.col(group.a[k]);
      group.length[k] = group.d[k].norm();
      group.lambda[k] = group.length[k] * m_inverseRestLength[spring];
      group.isInside = group.isInside && group.lambda[k] > kCollapsedLengthFraction &&
                       group.lambda[k] >= range.lower && group.lambda[k] <= range.upper;
    }
  };
  std::array<Group, 2> groups;
  std::size_t current = 0;
  Eigen::Index s = begin;
  if (s + 4 <= end) measure(s, groups[0]);
  for (; s + 4 <= end; s += 4, current ^= 1) {
    const Group& group = groups[current];
    if (s + 8 <= end) measure(s + 4, groups[current ^ 1]);
    if (group.isInside) {
      alignas(32) std::array<double, 4> stress{}, slope{};
      evaluateStressBatch<kWithSlope>(coefficients, group.lambda.data(), m_lambdaMax.data() + s,
                                      m_peaks.data() + s, stress.data(), slope.data());
      for (std::size_t k = 0; k < 4; ++k) {
        const double lambda = group.lambda[k];
        if constexpr (!withNodeStiffness) m_passStretch[s + static_cast<Eigen::Index>(k)] = lambda;
        report.minStretch = std::min(report.minStretch, lambda);
        report.maxStretch = std::max(report.maxStretch, lambda);
        applyStress<withBlocks, withNodeStiffness>(
            s + static_cast<Eigen::Index>(k), group.a[k], group.b[k], group.d[k], group.length[k],
            stress[k], slope[k], forces, blocks, nodeStiffness, isProjected);
      }
      continue;
    }
    // A spring outside what the batch handles: the scalar pass for the four.
    report.include(accumulateRange<withBlocks, withNodeStiffness>(s, s + 4, x, forces, blocks,
                                                                  nodeStiffness, isProjected));
  }
  report.include(accumulateRange<withBlocks, withNodeStiffness>(s, end, x, forces, blocks,
                                                                nodeStiffness, isProjected));
  return report;
#else
  return accumulateRange<withBlocks, withNodeStiffness>(begin, end, x, forces, blocks,
                                                        nodeStiffness, isProjected);
#endif
}

SpringFieldReport SpringForceField::addForces(const Eigen::Matrix3Xd& x,
                                              Eigen::Matrix3Xd& forces) const {
  return accumulate<false, false>(x, forces, nullptr, nullptr, true);
}

SpringFieldReport SpringForceField::addForcesAndStiffness(const Eigen::Matrix3Xd& x,
                                                          Eigen::Matrix3Xd& forces,
                                                          AxialBlocks& blocks,
                                                          bool isProjected) const {
  return accumulate<true, false>(x, forces, &blocks, nullptr, isProjected);
}

SpringFieldReport SpringForceField::addForcesAndNodeStiffness(
    const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces, Eigen::VectorXd& nodeStiffness) const {
  nodeStiffness.setZero();  // the passes add
  return accumulate<false, true>(x, forces, nullptr, &nodeStiffness, true);
}

double SpringForceField::frequencySquaredBound(const Eigen::Matrix3Xd& x) const {
  Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::VectorXd nodeStiffness(x.cols());
  addForcesAndNodeStiffness(x, scratch, nodeStiffness);
  return (2.0 * nodeStiffness.array() / m_mesh.nodeMass_kg.array()).maxCoeff();
}

void SpringForceField::commitStretchHistory(const Eigen::Matrix3Xd& x) {
  if (!m_law.isSoftening()) return;
  NodeRangeFlags isRangeUnmoved{};
  forEachNodeRange(m_pool, x.cols(), [&](int range, Eigen::Index begin, Eigen::Index end) {
    isRangeUnmoved[static_cast<std::size_t>(range)] =
        x.middleCols(begin, end - begin) == m_passPositions.middleCols(begin, end - begin);
  });
  if (allRanges(isRangeUnmoved)) {
    // The last pass's stretches, computed by the same expression at the same positions.
    const auto part = [&](int p) {
      const Eigen::Index end = partStart(p + 1);
      for (Eigen::Index s = partStart(p); s < end; ++s) {
        const double lambda = m_passStretch[s];
        if (lambda > m_lambdaMax[s]) {
          SofteningPeak& peak = m_peaks[static_cast<std::size_t>(s)];
          peak = m_law.peak(lambda);
          m_lambdaMax[s] = peak.lambdaMax;
        }
      }
    };
    runParts(m_pool, kSpringParts, part);
    return;
  }
  // Each spring's peak is its own: the ranges run on the pool with nothing to merge.
  const auto part = [&](int p) {
    const Eigen::Index end = partStart(p + 1);
    for (Eigen::Index s = partStart(p); s < end; ++s) {
      const Eigen::Vector3d d = x.col(m_mesh.springs(1, s)) - x.col(m_mesh.springs(0, s));
      const double inverseRestLength = m_inverseRestLength[s];
      const double lambdaMax = m_lambdaMax[s];
      // Most springs, most steps, are clearly below their peak: decided on squares, without a
      // square root, with a margin (1e-9) far above the rounding of either side.
      if (d.squaredNorm() * inverseRestLength * inverseRestLength <
          lambdaMax * lambdaMax * (1.0 - 1e-9)) {
        continue;
      }
      // The rest by the force pass's own expression, to the last bit: a peak recorded even one
      // unit in the last place above the stretch the pass computes would put the spring on its
      // softened branch just below lambda_max, where the tangent is all but vertical
      // (StressSoftening).
      const double lambda = d.norm() * inverseRestLength;
      if (lambda > lambdaMax) {
        SofteningPeak& peak = m_peaks[static_cast<std::size_t>(s)];
        peak = m_law.peak(lambda);
        m_lambdaMax[s] = peak.lambdaMax;
      }
    }
  };
  runParts(m_pool, kSpringParts, part);
}

}  // namespace tissuesim
