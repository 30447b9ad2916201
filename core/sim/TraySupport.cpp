// SPDX-License-Identifier: Apache-2.0
#include "sim/TraySupport.h"

#include <algorithm>

#include "mesh/TetLocator.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {
namespace {
/// The explicit integrator's damping per unit of a point's stiffness (s): the instrument's ratio
/// (6 N s/m per 10^4 N/m, CapsuleContactSettings).
constexpr double kDampingPerStiffness_s = 6e-4;
}  // namespace

TraySupport::TraySupport(const SceneGeometry& geometry, const SceneTray& tray)
    : m_up(tray.up.normalized()), m_height_m(tray.height_m) {
  if (geometry.surface && geometry.embedding) {
    const SurfaceEmbedding& embedding = *geometry.embedding;
    const Eigen::VectorXd area =
        vertexAreas(geometry.surface->vertices_m, geometry.surface->triangles);
    m_points.reserve(static_cast<std::size_t>(area.size()));
    for (Eigen::Index v = 0; v < area.size(); ++v) {
      CarriedSurfacePoint point;
      for (std::size_t k = 0; k < kMaxTermNodes; ++k)
        point.nodes[k] = embedding.nodes()(static_cast<Eigen::Index>(k), v);
      point.embedded = embedding.weights().col(v);
      point.carried = clampedToTet(point.embedded);
      point.stiffness_N_m = tray.stiffness_Pa_per_m * area[v];
      m_points.push_back(point);
    }
  } else {
    const Eigen::Matrix3Xi faces = boundaryFaces(geometry.mesh);
    const Eigen::VectorXd area = vertexAreas(geometry.mesh.nodes_m, faces);
    for (Eigen::Index node = 0; node < area.size(); ++node) {
      if (!(area[node] > 0.0)) continue;  // interior
      CarriedSurfacePoint point;
      point.nodes.fill(static_cast<int>(node));
      point.stiffness_N_m = tray.stiffness_Pa_per_m * area[node];
      m_points.push_back(point);
    }
  }
}

void TraySupport::findContacts(const Eigen::Matrix3Xd& x, PenaltyContactSet& contacts) const {
  for (std::size_t p = 0; p < m_points.size(); ++p) {
    const CarriedSurfacePoint& point = m_points[p];
    const Eigen::Vector3d drawn = point.drawn(x);
    const double height = m_up.dot(drawn);
    if (!(height < m_height_m + kDetectionMargin_m)) continue;
    PenaltyContact contact;
    contact.nodes = point.nodes;
    contact.weights = point.carried;
    contact.normal = -m_up;  // out of the tissue, into the tray
    // delta = h - up . (s + g) with g = drawn - s frozen for the step (s the carried point).
    contact.offset_m = m_up.dot(drawn - point.load(x)) - m_height_m;
    contact.stiffness_N_m = point.stiffness_N_m;
    contact.damping_N_s_m = kDampingPerStiffness_s * point.stiffness_N_m;
    contact.isSupport = true;
    contact.supportPoint = static_cast<int>(p);
    contacts.add(contact);
  }
}

double TraySupport::maxPenetration_m(const Eigen::Matrix3Xd& x) const {
  double deepest = 0.0;
  for (const CarriedSurfacePoint& point : m_points)
    deepest = std::max(deepest, m_height_m - m_up.dot(point.drawn(x)));
  return deepest;
}

Eigen::Vector3d TraySupport::force_N(const Eigen::Matrix3Xd& x) const {
  double total = 0.0;
  for (const CarriedSurfacePoint& point : m_points)
    total += point.stiffness_N_m * std::max(0.0, m_height_m - m_up.dot(point.drawn(x)));
  return total * m_up;
}

}  // namespace tissuesim
