#include "CapsuleContact.h"

#include <cmath>

#include "SegmentTriangleDistance.h"

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

void CapsuleContact::findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                                  PenaltyContactSet& contacts) {
  for (std::size_t i = 0; i < m_surfaceNodes.size(); ++i) {
    m_vertices.row(static_cast<Eigen::Index>(i)) = x.col(m_surfaceNodes[i]).transpose();
  }
  m_bvh->refit(m_vertices);

  // The capsule's axis segment: from the tip's hemisphere centre back along the shaft. The
  // query capsule is half a radius fatter, to catch triangles about to be touched.
  const double radius = m_settings.radius_m;
  const double margin = 0.5 * radius;
  const Eigen::Vector3d axisEnd = pose.tip_m - radius * pose.direction;
  const Eigen::Vector3d axisStart = axisEnd - m_settings.length_m * pose.direction;
  Capsule capsule{radius + margin, m_settings.length_m, Eigen::Isometry3d::Identity()};
  capsule.pose.translation() = 0.5 * (axisStart + axisEnd);
  capsule.pose.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), pose.direction)
          .toRotationMatrix();
  m_bvh->touchedTriangles(capsule, m_touched);

  // Each touched triangle is held out of the capsule at its point p nearest the axis (c on the
  // axis): p must stay at least r from c along u = (p - c) / |p - c|, the way the capsule's
  // surface faces there. At the tip that is the face's inward normal (the tip carries the face
  // ahead of it); beside the shaft it is radial (the shaft holds the walls of the dent apart).
  // Taking the direction from the capsule rather than from the triangle's normal keeps a face
  // that the shaft has passed through being pushed back out instead of along the shaft.
  for (const int f : m_touched) {
    const int ia = m_surfaceNodes[static_cast<std::size_t>(m_faces(0, f))];
    const int ib = m_surfaceNodes[static_cast<std::size_t>(m_faces(1, f))];
    const int ic = m_surfaceNodes[static_cast<std::size_t>(m_faces(2, f))];
    const Eigen::Vector3d a = x.col(ia), b = x.col(ib), c = x.col(ic);
    const Eigen::Vector3d faceNormal = (b - a).cross(c - a);
    if (faceNormal.squaredNorm() == 0.0) continue;  // degenerate: no face to push
    const SegmentTriangleClosest closest = closestSegmentTriangle(axisStart, axisEnd, a, b, c);
    if (closest.distance >= radius + margin) continue;
    Eigen::Vector3d away = closest.onTriangle - closest.onSegment;
    Eigen::Vector3d onAxis = closest.onSegment;
    if (closest.distance > 1e-6 * radius) {
      away /= closest.distance;
    } else if (std::abs(faceNormal.normalized().dot(pose.direction)) >= std::sqrt(0.5)) {
      // The axis runs through a face that lies across it: the tip went through; the face
      // belongs ahead of the tip.
      away = pose.direction;
      onAxis = axisEnd;
    } else {
      // The axis runs through a face along it: push the face radially off the axis, towards
      // its centroid.
      away = (a + b + c) / 3.0 - closest.onSegment;
      away -= away.dot(pose.direction) * pose.direction;
      if (away.norm() <= 1e-6 * radius) continue;
      away.normalize();
    }
    // penetration = r - u . (s(x) - c) = n . s(x) - offset with n = -u.
    contacts.add({{ia, ib, ic},
                  closest.weights,
                  -away,
                  -(radius + away.dot(onAxis)),
                  m_settings.stiffness_N_m,
                  m_settings.damping_N_s_m});
  }
}

}  // namespace tissuesim
