// SPDX-License-Identifier: Apache-2.0
#include "material/StiffnessTable.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tissuesim {
namespace {

/// Nodes per gap to the locking stretch: h = gap / 20 bounds the relative error by 4e-7.
constexpr double kNodesPerLockingGap = 20.0;
/// Never coarser than this, whatever the tissue (dimensionless stretch).
constexpr double kMaxSpacing = 1e-3;
/// The table covers no stretch beyond [1 / this, this]: soft tissue tears long before (liver
/// near 1.4-1.6), and a nearly Gaussian network (large N) locks only near sqrt(3 N), which
/// would make the table as long as that is far (N = 10^6: millions of nodes, bad_alloc).
constexpr double kMaxTableStretch = 3.0;
}  // namespace

HermiteNode StiffnessTable::closedFormStiffness(const StrainEnergy& energy, double lambda) {
  // k_s = 2 v W / (lambda^2 - lambda) = 2 v g(lambda) Q(I1), with
  // g = (lambda - 1)(lambda + 2) / lambda^2 = 1 + 1/lambda - 2/lambda^2 (see the header).
  const double area = energy.parameters().springArea_m2;
  const SecantFromRest q = energy.secantFromRest(StrainEnergy::invariantShift(lambda));
  const double l2 = lambda * lambda;
  const double g = (lambda - 1.0) * (lambda + 2.0) / l2;
  const double dg = -1.0 / l2 + 4.0 / (l2 * lambda);
  const double dI = StrainEnergy::invariantSlope(lambda);
  return {2.0 * area * g * q.value, 2.0 * area * (dg * q.value + g * q.slope * dI)};
}

StiffnessTable::StiffnessTable(const StrainEnergy& energy)
    : m_range(energy.usableRange()), m_halfInverseArea(0.5 / energy.parameters().springArea_m2) {
  m_range = {std::max(m_range.lower, 1.0 / kMaxTableStretch),
             std::min(m_range.upper, kMaxTableStretch)};
  const StretchRange locking = energy.lockingRange();
  const double gap = std::min(m_range.lower - locking.lower, locking.upper - m_range.upper);
  const double spacing = std::min(kMaxSpacing, gap / kNodesPerLockingGap);
  // Nodes at 1 + i h, from the first at or below the usable lower end to the first at or
  // above the upper end, then pulled inside so no node leaves the usable range.
  const auto first = static_cast<long>(std::ceil((m_range.lower - 1.0) / spacing));
  const auto last = static_cast<long>(std::floor((m_range.upper - 1.0) / spacing));
  const double origin = 1.0 + static_cast<double>(first) * spacing;
  const auto count = static_cast<std::size_t>(last - first + 1);
  m_range = {origin, 1.0 + static_cast<double>(last) * spacing};

  std::vector<HermiteNode> stressNodes(count);
  std::vector<HermiteNode> stiffnessNodes(count);
  for (std::size_t i = 0; i < count; ++i) {
    // 1 + k h rather than origin + i h, so the node at lambda = 1 is exact.
    const double lambda = 1.0 + static_cast<double>(first + static_cast<long>(i)) * spacing;
    stressNodes[i] = energy.stressAndSlope(lambda);
    stiffnessNodes[i] = closedFormStiffness(energy, lambda);
  }
  m_stress = UniformHermiteSpline(origin, spacing, std::move(stressNodes));
  m_stiffness = UniformHermiteSpline(origin, spacing, std::move(stiffnessNodes));
}

}  // namespace tissuesim
