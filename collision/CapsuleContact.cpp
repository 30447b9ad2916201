// SPDX-License-Identifier: Apache-2.0
#include "collision/CapsuleContact.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mesh/SegmentTriangleDistance.h"
#include "mesh/TetLocator.h"

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
  Eigen::MatrixX3d rest(static_cast<Eigen::Index>(m_surfaceNodes.size()), 3);
  for (std::size_t i = 0; i < m_surfaceNodes.size(); ++i) {
    rest.row(static_cast<Eigen::Index>(i)) = mesh.nodes_m.col(m_surfaceNodes[i]).transpose();
  }
  buildBvh(rest);
}

CapsuleContact::CapsuleContact(const TetMesh& mesh, const TriangleSurface& visual,
                               const SurfaceEmbedding& embedding, CapsuleContactSettings settings)
    : m_settings(settings), m_faces(visual.triangles), m_embedding(&embedding) {
  // Each face is carried by one tet: the one holding its centroid at rest (among those near the
  // face and those carrying its corners, which hold it where the surface lies outside the mesh).
  // One tet a face, not one a contact point: a point sliding across a tet boundary moved its
  // force to other nodes at once, and the tip's contacts chattered (0.45 -> 0.62 -> 0.56 N from
  // one 50 ms to the next, pressing steadily).
  const TetLocator locator(mesh);
  m_carriers.reserve(static_cast<std::size_t>(m_faces.cols()));
  std::vector<int> candidates;
  for (Eigen::Index f = 0; f < m_faces.cols(); ++f) {
    Eigen::Vector3d lower = visual.vertices_m.col(m_faces(0, f)), upper = lower;
    for (int k = 1; k < 3; ++k) {
      lower = lower.cwiseMin(visual.vertices_m.col(m_faces(k, f)));
      upper = upper.cwiseMax(visual.vertices_m.col(m_faces(k, f)));
    }
    candidates.clear();
    for (int k = 0; k < 3; ++k)
      candidates.push_back(embedding.tets()[static_cast<std::size_t>(m_faces(k, f))]);
    locator.tetsNear(lower, upper, candidates);
    const Eigen::Vector3d centroid =
        (visual.vertices_m.col(m_faces(0, f)) + visual.vertices_m.col(m_faces(1, f)) +
         visual.vertices_m.col(m_faces(2, f))) /
        3.0;
    const int tet = locator.locateAmong(candidates, centroid).tet;
    FaceCarrier carrier;
    for (int k = 0; k < 4; ++k) carrier.nodes[static_cast<std::size_t>(k)] = mesh.tets(k, tet);
    for (int k = 0; k < 3; ++k)
      carrier.cornerWeights.col(k) = locator.weightsIn(tet, visual.vertices_m.col(m_faces(k, f)));
    m_carriers.push_back(carrier);
  }
  buildBvh(visual.vertices_m.transpose());
}

void CapsuleContact::buildBvh(const Eigen::MatrixX3d& restVertices) {
  m_vertices = restVertices;
  m_bvh = std::make_unique<SurfaceBvh>(m_vertices, m_faces.transpose());
  m_touched.reserve(static_cast<std::size_t>(m_faces.cols()));
  m_features.reserve(static_cast<std::size_t>(m_faces.cols()));
}

CapsuleContact::~CapsuleContact() = default;

void CapsuleContact::carry(Eigen::Index f, const Eigen::Vector3d& onTriangle,
                           PenaltyContact& contact) const {
  if (m_embedding == nullptr) {
    for (int k = 0; k < 3; ++k) {
      contact.nodes[static_cast<std::size_t>(k)] =
          m_surfaceNodes[static_cast<std::size_t>(m_faces(k, f))];
    }
    contact.nodes[3] = contact.nodes[0];
    contact.weights << onTriangle, 0.0;
    return;
  }
  // The point at rest, in the tet that carries its face.
  const FaceCarrier& carrier = m_carriers[static_cast<std::size_t>(f)];
  contact.nodes = carrier.nodes;
  const Eigen::Vector4d weights = carrier.cornerWeights * onTriangle;
  // A point outside the tet (the drawn surface reaches past the lattice by up to half a tet on
  // the bundled liver) is carried by the tet's nearest point: extrapolated weights (as low as
  // -0.45 there) made each contact a lever on the tet, and the tip's one or two contacts
  // chattered (0.5 -> 2.3 -> 0 N from step to step) until the contact was lost mid-poke.
  contact.weights = clampedToTet(weights);
}

namespace {
/// Where the shaft holds a face: four fixed points inside it (barycentric), its centroid and one
/// towards each corner, none on an edge, so no point is shared with a neighbouring face.
const std::array<Eigen::Vector3d, 4> kShaftSamples{
    Eigen::Vector3d(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0),
    Eigen::Vector3d(2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0),
    Eigen::Vector3d(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0),
    Eigen::Vector3d(1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0)};
}  // namespace

void CapsuleContact::findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                                  PenaltyContactSet& contacts) {
  if (m_embedding != nullptr) {
    for (Eigen::Index v = 0; v < m_vertices.rows(); ++v)
      m_vertices.row(v) = m_embedding->position(v, x).transpose();
  } else {
    for (std::size_t i = 0; i < m_surfaceNodes.size(); ++i)
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
  m_features.clear();
  const auto addContact = [&](Eigen::Index f, const Eigen::Vector3d& weights,
                              const Eigen::Vector3d& drawnPoint, const Eigen::Vector3d& away,
                              const Eigen::Vector3d& onAxis, double share) {
    // penetration = r - u . (s(x) - c) = n . s(x) - offset with n = -u.
    PenaltyContact contact;
    carry(f, weights, contact);
    contact.normal = -away;
    // The carried point s(x) may lie off the drawn point p (outside the lattice, or where the
    // drawn triangle and the tet's interpolation differ): the step's contact is s(x) + (p - s(x))
    // with the gap frozen, so the penetration at the current state is the drawn surface's own.
    const Eigen::Vector3d gap = drawnPoint - contact.point(x);
    contact.offset_m = -(radius + away.dot(onAxis)) - contact.normal.dot(gap);
    contact.stiffness_N_m = share * m_settings.stiffness_N_m;
    contact.damping_N_s_m = share * m_settings.damping_N_s_m;
    contacts.add(contact);
  };
  for (const int f : m_touched) {
    const Eigen::Vector3d a = m_vertices.row(m_faces(0, f)).transpose();
    const Eigen::Vector3d b = m_vertices.row(m_faces(1, f)).transpose();
    const Eigen::Vector3d c = m_vertices.row(m_faces(2, f)).transpose();
    const Eigen::Vector3d faceNormal = (b - a).cross(c - a);
    if (faceNormal.squaredNorm() == 0.0) continue;  // degenerate: no face to push
    const SegmentTriangleClosest closest = closestSegmentTriangle(axisStart, axisEnd, a, b, c);
    if (closest.distance >= radius + margin) continue;
    // How far up the shaft the face lies (its centroid; not its nearest point, which jumps
    // along a face that lies along the axis): 0 at the tip's centre and ahead of it, 1 from a
    // radius up. The tip holds each face at its nearest point; the shaft at fixed points.
    const double upShaft =
        std::clamp(((a + b + c) / 3.0 - axisEnd).dot(-pose.direction) / radius, 0.0, 1.0);
    const double shaftShare = upShaft * upShaft * (3.0 - 2.0 * upShaft);
    if (shaftShare > 0.0) {
      for (const Eigen::Vector3d& weights : kShaftSamples) {
        const Eigen::Vector3d q = weights[0] * a + weights[1] * b + weights[2] * c;
        const double along =
            std::clamp((q - axisStart).dot(pose.direction), 0.0, m_settings.length_m);
        const Eigen::Vector3d onAxis = axisStart + along * pose.direction;
        Eigen::Vector3d away = q - onAxis;
        const double distance = away.norm();
        if (distance >= radius + margin || distance <= 1e-6 * radius) continue;
        away /= distance;
        addContact(f, weights, q, away, onAxis, shaftShare);
      }
    }
    if (shaftShare == 1.0) continue;
    if (!isFirstAtFeature(f, closest.weights)) continue;
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
    addContact(f, closest.weights, closest.onTriangle, away, onAxis, 1.0 - shaftShare);
  }
}

bool CapsuleContact::isFirstAtFeature(Eigen::Index f, const Eigen::Vector3d& weights) {
  std::array<int, 3> corners{};
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    if (weights[k] != 0.0) corners[static_cast<std::size_t>(count++)] = m_faces(k, f);
  }
  if (count == 3) return true;  // inside the face: its own
  const int low = count == 1 ? corners[0] : std::min(corners[0], corners[1]);
  const int high = count == 1 ? corners[0] : std::max(corners[0], corners[1]);
  const std::uint64_t key = static_cast<std::uint64_t>(static_cast<std::uint32_t>(low)) << 32 |
                            static_cast<std::uint32_t>(high);
  if (std::find(m_features.begin(), m_features.end(), key) != m_features.end()) return false;
  m_features.push_back(key);
  return true;
}

std::unique_ptr<CapsuleContact> makeInstrumentContact(const Simulation& simulation) {
  const SceneDescription& scene = simulation.scene();
  const CapsuleContactSettings settings{scene.instrument->shaftRadius_m,
                                        scene.instrument->shaftLength_m};
  const SceneGeometry& geometry = simulation.geometry();
  if (geometry.surface && geometry.embedding) {
    return std::make_unique<CapsuleContact>(geometry.mesh, *geometry.surface, *geometry.embedding,
                                            settings);
  }
  return std::make_unique<CapsuleContact>(geometry.mesh, settings);
}

}  // namespace tissuesim
