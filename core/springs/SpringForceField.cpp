#include "springs/SpringForceField.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {
namespace {
/// Below this fraction of its rest length a spring has no usable direction.
constexpr double kCollapsedLengthFraction = 1e-9;
}  // namespace

SpringForceField::SpringForceField(const SpringMesh& mesh, const SpringForceLaw& law)
    : m_mesh(mesh),
      m_law(law),
      m_lambdaMax(Eigen::VectorXd::Ones(mesh.springCount())),
      m_nodeStiffness(Eigen::VectorXd::Zero(mesh.nodeCount())) {}

template <bool withStiffness>
SpringFieldReport SpringForceField::accumulate(
    const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
    Eigen::Matrix<double, 9, Eigen::Dynamic>* blocks) const {
  SpringFieldReport report;
  const Eigen::Index count = m_mesh.springCount();
  for (Eigen::Index s = 0; s < count; ++s) {
    const int a = m_mesh.springs(0, s);
    const int b = m_mesh.springs(1, s);
    const Eigen::Vector3d d = x.col(b) - x.col(a);
    const double length = d.norm();
    const double restLength = m_mesh.restLength_m[s];
    if (!(length > kCollapsedLengthFraction * restLength)) {
      ++report.collapsedCount;
      if constexpr (withStiffness) blocks->col(s).setZero();
      continue;
    }
    const double lambda = length / restLength;
    report.minStretch = std::min(report.minStretch, lambda);
    report.maxStretch = std::max(report.maxStretch, lambda);
    const SpringStress p = m_law.evaluate(lambda, m_lambdaMax[s]);
    report.beyondRangeCount += p.isBeyondRange ? 1 : 0;
    const double areaOverLength = m_mesh.volume_m3[s] / restLength;  // V_e / L0 (m^2)
    const Eigen::Vector3d n = d / length;
    const Eigen::Vector3d f = (areaOverLength * p.stress) * n;
    forces.col(a) += f;
    forces.col(b) -= f;
    if constexpr (withStiffness) {
      const double axial = std::max(0.0, areaOverLength * p.slope / restLength);
      const double lateral = std::max(0.0, areaOverLength * p.stress / length);
      Eigen::Map<Eigen::Matrix3d> k(blocks->col(s).data());
      k.noalias() = (axial - lateral) * (n * n.transpose());
      k.diagonal().array() += lateral;
    }
  }
  return report;
}

SpringFieldReport SpringForceField::addForces(const Eigen::Matrix3Xd& x,
                                              Eigen::Matrix3Xd& forces) const {
  return accumulate<false>(x, forces, nullptr);
}

SpringFieldReport SpringForceField::addForcesAndStiffness(
    const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
    Eigen::Matrix<double, 9, Eigen::Dynamic>& blocks) const {
  return accumulate<true>(x, forces, &blocks);
}

double SpringForceField::frequencySquaredBound(const Eigen::Matrix3Xd& x) const {
  m_nodeStiffness.setZero();
  for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) {
    const int a = m_mesh.springs(0, s);
    const int b = m_mesh.springs(1, s);
    const double restLength = m_mesh.restLength_m[s];
    const double length = (x.col(b) - x.col(a)).norm();
    const double lambda = std::max(length, kCollapsedLengthFraction * restLength) / restLength;
    const SpringStress p = m_law.evaluate(lambda, m_lambdaMax[s]);
    const double areaOverLength = m_mesh.volume_m3[s] / restLength;
    const double norm = std::max({std::abs(areaOverLength * p.slope / restLength),
                                  std::abs(areaOverLength * p.stress / (lambda * restLength))});
    m_nodeStiffness[a] += norm;
    m_nodeStiffness[b] += norm;
  }
  return (2.0 * m_nodeStiffness.array() / m_mesh.nodeMass_kg.array()).maxCoeff();
}

void SpringForceField::commitStretchHistory(const Eigen::Matrix3Xd& x) {
  if (!m_law.isSoftening()) return;
  for (Eigen::Index s = 0; s < m_mesh.springCount(); ++s) {
    const double lambda =
        (x.col(m_mesh.springs(1, s)) - x.col(m_mesh.springs(0, s))).norm() / m_mesh.restLength_m[s];
    m_lambdaMax[s] = std::max(m_lambdaMax[s], lambda);
  }
}

}  // namespace tissuesim
