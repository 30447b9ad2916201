#include "CapsuleContact.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {

CapsuleContact::CapsuleContact(const TetMesh& mesh, CapsuleContactSettings settings)
    : m_settings(settings) {
  const Eigen::Matrix3Xi faces = boundaryFaces(mesh);
  std::vector<int> local(static_cast<std::size_t>(mesh.nodeCount()), -1);
  m_faces.resize(3, faces.cols());
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    for (int k = 0; k < 3; ++k) {
      int& index = local[static_cast<std::size_t>(faces(k, f))];
      if (index < 0) {
        index = static_cast<int>(m_surfaceNodes.size());
        m_surfaceNodes.push_back(faces(k, f));
      }
      m_faces(k, f) = index;
    }
  }
  m_vertices.resize(static_cast<Eigen::Index>(m_surfaceNodes.size()), 3);
  for (std::size_t i = 0; i < m_surfaceNodes.size(); ++i) {
    m_vertices.row(static_cast<Eigen::Index>(i)) = mesh.nodes_m.col(m_surfaceNodes[i]).transpose();
  }
  m_bvh = std::make_unique<SurfaceBvh>(m_vertices, m_faces.transpose());
  m_isTouched.assign(m_surfaceNodes.size(), 0);
  m_touched.reserve(m_surfaceNodes.size());
}

CapsuleContact::~CapsuleContact() = default;

ContactResult CapsuleContact::addContactForces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                                               const InstrumentPose& pose, Eigen::Matrix3Xd& forces) {
  ContactResult result;
  for (std::size_t i = 0; i < m_surfaceNodes.size(); ++i) {
    m_vertices.row(static_cast<Eigen::Index>(i)) = x.col(m_surfaceNodes[i]).transpose();
  }
  m_bvh->refit(m_vertices);

  // The capsule's axis segment: from the tip's hemisphere centre back along the shaft.
  const Eigen::Vector3d axisEnd = pose.tip_m - m_settings.radius_m * pose.direction;
  const Eigen::Vector3d axisStart = axisEnd - m_settings.length_m * pose.direction;
  Capsule capsule{m_settings.radius_m, m_settings.length_m, Eigen::Isometry3d::Identity()};
  capsule.pose.translation() = 0.5 * (axisStart + axisEnd);
  capsule.pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), pose.direction).toRotationMatrix();
  m_bvh->touchedTriangles(capsule, m_touched);
  if (m_touched.empty()) return result;

  // Each touched triangle resists the capsule's penetration through its plane: the axis point
  // nearest the triangle, c, lies at signed height d = (c - q) . n above it (q on the triangle,
  // n its outward normal); below r the triangle is pushed inward by k (r - d), the force spread
  // to its corners by the barycentric weights of c's projection, so a probe between nodes is
  // caught by the face, not only by its vertices.
  const Eigen::Vector3d axis = axisEnd - axisStart;
  for (const int f : m_touched) {
    const int ia = m_surfaceNodes[static_cast<std::size_t>(m_faces(0, f))];
    const int ib = m_surfaceNodes[static_cast<std::size_t>(m_faces(1, f))];
    const int ic = m_surfaceNodes[static_cast<std::size_t>(m_faces(2, f))];
    const Eigen::Vector3d a = x.col(ia), b = x.col(ib), c = x.col(ic);
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double twiceArea = normal.norm();
    if (twiceArea == 0.0) continue;
    normal /= twiceArea;
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    const double s = std::clamp((centroid - axisStart).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector3d onAxis = axisStart + s * axis;
    const double height = (onAxis - a).dot(normal);
    const double penetration = m_settings.radius_m - height;
    if (penetration <= 0.0 || penetration > 2.0 * m_settings.radius_m) continue;
    // Barycentric weights of the projection, clamped onto the triangle.
    const Eigen::Vector3d p = onAxis - height * normal;
    Eigen::Vector3d w((b - p).cross(c - p).dot(normal), (c - p).cross(a - p).dot(normal),
                      (a - p).cross(b - p).dot(normal));
    w = w.cwiseMax(0.0);
    if (w.sum() <= 0.0) continue;
    w /= w.sum();
    const Eigen::Vector3d velocity = w[0] * v.col(ia) + w[1] * v.col(ib) + w[2] * v.col(ic);
    const double push = std::max(0.0, m_settings.stiffness_N_m * penetration +
                                          m_settings.damping_N_s_m * velocity.dot(normal));
    const Eigen::Vector3d onTissue = -push * normal;
    forces.col(ia) += w[0] * onTissue;
    forces.col(ib) += w[1] * onTissue;
    forces.col(ic) += w[2] * onTissue;
    result.toolForce_N -= onTissue;
    result.toolTorque_Nm -= (p - pose.tip_m).cross(onTissue);
    result.maxPenetration_m = std::max(result.maxPenetration_m, penetration);
    ++result.contactNodes;
  }
  return result;
}

}  // namespace tissuesim
