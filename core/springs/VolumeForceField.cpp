#include "springs/VolumeForceField.h"

#include <algorithm>
#include <array>

#include "mesh/TetMesh.h"

namespace tissuesim {
namespace {
/// dV/dx for the four nodes of a tet, as a 3 by 4 matrix.
Eigen::Matrix<double, 3, 4> volumeGradient(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                           const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  Eigen::Matrix<double, 3, 4> g;
  g.col(1) = (c - a).cross(d - a) / 6.0;
  g.col(2) = (d - a).cross(b - a) / 6.0;
  g.col(3) = (b - a).cross(c - a) / 6.0;
  g.col(0) = -(g.col(1) + g.col(2) + g.col(3));
  return g;
}
}  // namespace

VolumeForceField::VolumeForceField(const SpringMesh& mesh, double bulkModulus_Pa)
    : m_mesh(mesh), m_bulkModulus_Pa(bulkModulus_Pa) {}

VolumeFieldReport VolumeForceField::addForces(
    const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
    Eigen::Matrix<double, 144, Eigen::Dynamic>* blocks) const {
  VolumeFieldReport report;
  for (Eigen::Index t = 0; t < m_mesh.tets.cols(); ++t) {
    const auto node = [&](int i) { return m_mesh.tets(i, t); };
    const double restVolume = m_mesh.tetRestVolume_m3[t];
    const double ratio = signedTetVolume(x, m_mesh.tets, t) / restVolume;
    report.minVolumeRatio = std::min(report.minVolumeRatio, ratio);
    report.invertedTetCount += ratio <= 0.0 ? 1 : 0;
    const Eigen::Matrix<double, 3, 4> g =
        volumeGradient(x.col(node(0)), x.col(node(1)), x.col(node(2)), x.col(node(3)));
    const double pressure = m_bulkModulus_Pa * (ratio - 1.0);  // dE/dV (Pa)
    for (int i = 0; i < 4; ++i) forces.col(node(i)) -= pressure * g.col(i);
    if (blocks != nullptr) {
      const Eigen::Map<const Eigen::Matrix<double, 12, 1>> flat(g.data());
      Eigen::Map<Eigen::Matrix<double, 12, 12>> h(blocks->col(t).data());
      h.noalias() = (m_bulkModulus_Pa / restVolume) * flat * flat.transpose();
    }
  }
  return report;
}

VolumeFieldReport VolumeForceField::inspect(const SpringMesh& mesh, const Eigen::Matrix3Xd& x,
                                            ForkJoinPool* pool) {
  std::array<VolumeFieldReport, kInspectParts> parts;
  const Eigen::Index tets = mesh.tets.cols();
  const auto part = [&](int p) {
    VolumeFieldReport& report = parts[static_cast<std::size_t>(p)];
    const Eigen::Index end = tets * (p + 1) / kInspectParts;
    for (Eigen::Index t = tets * p / kInspectParts; t < end; ++t) {
      const double ratio = signedTetVolume(x, mesh.tets, t) / mesh.tetRestVolume_m3[t];
      report.minVolumeRatio = std::min(report.minVolumeRatio, ratio);
      report.invertedTetCount += ratio <= 0.0 ? 1 : 0;
    }
  };
  runParts(pool, kInspectParts, part);
  VolumeFieldReport report;
  for (const VolumeFieldReport& r : parts) {
    report.minVolumeRatio = std::min(report.minVolumeRatio, r.minVolumeRatio);
    report.invertedTetCount += r.invertedTetCount;
  }
  return report;
}

double VolumeForceField::stiffnessBound(Eigen::Index t, const Eigen::Matrix3Xd& x) const {
  const Eigen::Matrix<double, 3, 4> g =
      volumeGradient(x.col(m_mesh.tets(0, t)), x.col(m_mesh.tets(1, t)), x.col(m_mesh.tets(2, t)),
                     x.col(m_mesh.tets(3, t)));
  return m_bulkModulus_Pa / m_mesh.tetRestVolume_m3[t] * g.squaredNorm();
}

}  // namespace tissuesim
