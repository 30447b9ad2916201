// SPDX-License-Identifier: Apache-2.0
#include "collision/SurfaceBvh.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/fcl.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include "mesh/SegmentTriangleDistance.h"

namespace tissuesim {
namespace {

using MeshCapsuleNode =
    fcl::detail::MeshShapeCollisionTraversalNode<fcl::AABBd, fcl::Capsuled,
                                                 fcl::detail::GJKSolver_indep<double>>;

/// FCL's traversal of the tree against the capsule's box, with our own leaf test: the exact
/// distance from the capsule's axis to the triangle (SegmentTriangleDistance) against its radius.
/// FCL's test (GJK, then EPA whenever the shapes overlap, whatever the request asks for)
/// allocated 19 KB for each overlapping triangle, every step the tool touched.
class CapsuleTriangleTraversal final : public MeshCapsuleNode {
 public:
  Eigen::Vector3d axisStart_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d axisEnd_m = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
  std::vector<int>* touched = nullptr;

  void leafTesting(int b1, int /*b2*/) const override {
    const int triangle = this->model1->getBV(b1).primitiveId();
    const fcl::Triangle& corners = this->tri_indices[triangle];
    const SegmentTriangleClosest closest =
        closestSegmentTriangle(axisStart_m, axisEnd_m, this->vertices[corners[0]],
                               this->vertices[corners[1]], this->vertices[corners[2]]);
    if (closest.distance <= radius_m) touched->push_back(triangle);
  }
};

}  // namespace

struct SurfaceBvh::Impl {
  // AABBs: refitting them is a min/max pass, where OBBRSS refits need an eigen-decomposition per
  // node (4 ms a step on the liver's 1,408 triangles against 0.1 ms). FCL's mesh distance
  // needs OBBRSS, so distanceTo() builds one from the model's current vertices when asked.
  std::shared_ptr<fcl::BVHModel<fcl::AABBd>> model;
  // Kept between steps so a query allocates nothing: the capsule, the solver, the result.
  // FCL's own GJK (GST_INDEP), not libccd's: libccd's MPR test loops forever on some touching
  // configurations (FCL issue #243, libccd #7); it hung here on a quasi-Newton poke of the liver.
  std::unique_ptr<fcl::Capsuled> capsule;
  fcl::detail::GJKSolver_indep<double> solver;
  fcl::CollisionResultd result;
  /// The tree's nodes, children before parents (post-order from the root): the refit's order.
  std::vector<int> refitOrder;
  /// The triangles' corners as plain ints: fcl::Triangle's operator[] is an out-of-line call.
  std::vector<std::array<int, 3>> corners;
  int vertexCount = 0;
  int triangleCount = 0;
};

namespace {
void copyVertices(const Eigen::Ref<const Eigen::MatrixX3d>& vertices,
                  std::vector<fcl::Vector3d>& points) {
  points.resize(static_cast<std::size_t>(vertices.rows()));
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) {
    points[static_cast<std::size_t>(i)] = vertices.row(i).transpose();
  }
}
}  // namespace

SurfaceBvh::SurfaceBvh(const Eigen::Ref<const Eigen::MatrixX3d>& vertices,
                       const Eigen::Ref<const Eigen::MatrixX3i>& triangles)
    : m_impl(std::make_unique<Impl>()) {
  if (vertices.rows() == 0 || triangles.rows() == 0) {
    throw std::invalid_argument("a collision surface needs at least one vertex and one triangle");
  }
  if (triangles.minCoeff() < 0 || triangles.maxCoeff() >= vertices.rows()) {
    throw std::invalid_argument("a collision triangle refers to a vertex outside 0.." +
                                std::to_string(vertices.rows() - 1));
  }
  m_impl->vertexCount = static_cast<int>(vertices.rows());
  m_impl->triangleCount = static_cast<int>(triangles.rows());
  std::vector<fcl::Vector3d> points;
  copyVertices(vertices, points);
  std::vector<fcl::Triangle> faces;
  faces.reserve(static_cast<std::size_t>(triangles.rows()));
  for (Eigen::Index i = 0; i < triangles.rows(); ++i) {
    faces.emplace_back(static_cast<std::size_t>(triangles(i, 0)),
                       static_cast<std::size_t>(triangles(i, 1)),
                       static_cast<std::size_t>(triangles(i, 2)));
  }
  m_impl->model = std::make_shared<fcl::BVHModel<fcl::AABBd>>();
  m_impl->model->beginModel(static_cast<int>(faces.size()), static_cast<int>(points.size()));
  m_impl->model->addSubModel(points, faces);
  m_impl->model->endModel();
  for (Eigen::Index i = 0; i < triangles.rows(); ++i) {
    m_impl->corners.push_back({triangles(i, 0), triangles(i, 1), triangles(i, 2)});
  }
  // Post-order by an explicit stack: a node is listed once both its children are.
  const fcl::BVHModel<fcl::AABBd>& model = *m_impl->model;
  std::vector<std::pair<int, bool>> stack{{0, false}};
  while (!stack.empty()) {
    const auto [id, isExpanded] = stack.back();
    stack.pop_back();
    const int firstChild = model.getBV(id).first_child;
    if (isExpanded || firstChild < 0) {
      m_impl->refitOrder.push_back(id);
      continue;
    }
    stack.push_back({id, true});
    stack.push_back({firstChild + 1, false});
    stack.push_back({firstChild, false});
  }
}

SurfaceBvh::~SurfaceBvh() = default;

void SurfaceBvh::refit(const Eigen::Ref<const Eigen::MatrixX3d>& vertices) {
  if (vertices.rows() != m_impl->vertexCount) {
    throw std::invalid_argument("refit needs " + std::to_string(m_impl->vertexCount) +
                                " vertices, got " + std::to_string(vertices.rows()));
  }
  // FCL's own refit (beginReplaceModel .. endReplaceModel(refit, bottom-up)) took 0.1 ms a step
  // on the liver's 1,408 triangles, most of the contact query: a recursion through out-of-line
  // calls per node (isLeaf, Triangle's [], AABB's +=). The same boxes are computed here in one
  // loop over the nodes, children first: each leaf's box is its triangle's corners' min and max,
  // each inner node's the union of its children's (what FCL's fit and operator+ give, to the
  // bit). Only the current vertices are kept (no previous frame: FCL's continuous queries,
  // which need it, are not made), and the narrow phase reads them from the model.
  fcl::BVHModel<fcl::AABBd>& model = *m_impl->model;
  for (Eigen::Index i = 0; i < vertices.rows(); ++i)
    model.vertices[i] = vertices.row(i).transpose();
  for (const int id : m_impl->refitOrder) {
    fcl::BVNode<fcl::AABBd>& node = model.getBV(id);
    if (node.first_child < 0) {
      const std::array<int, 3>& t =
          m_impl->corners[static_cast<std::size_t>(-(node.first_child + 1))];
      const fcl::Vector3d& a = model.vertices[t[0]];
      const fcl::Vector3d& b = model.vertices[t[1]];
      const fcl::Vector3d& c = model.vertices[t[2]];
      node.bv.min_ = a.cwiseMin(b).cwiseMin(c);
      node.bv.max_ = a.cwiseMax(b).cwiseMax(c);
    } else {
      const fcl::AABBd& left = model.getBV(node.first_child).bv;
      const fcl::AABBd& right = model.getBV(node.first_child + 1).bv;
      node.bv.min_ = left.min_.cwiseMin(right.min_);
      node.bv.max_ = left.max_.cwiseMax(right.max_);
    }
  }
}

CapsuleSurfaceDistance SurfaceBvh::distanceTo(const Capsule& capsule) const {
  auto shape = std::make_shared<fcl::Capsuled>(capsule.radius_m, capsule.length_m);
  const fcl::CollisionObjectd tool(shape, capsule.pose);
  auto distanceModel = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  const fcl::BVHModel<fcl::AABBd>& model = *m_impl->model;
  // The model's own vertices and triangles (FCL keeps the triangles in the order given).
  const std::vector<fcl::Vector3d> points(model.vertices, model.vertices + m_impl->vertexCount);
  const std::vector<fcl::Triangle> faces(model.tri_indices,
                                         model.tri_indices + m_impl->triangleCount);
  distanceModel->beginModel(m_impl->triangleCount, m_impl->vertexCount);
  distanceModel->addSubModel(points, faces);
  distanceModel->endModel();
  const fcl::CollisionObjectd surface(distanceModel, fcl::Transform3d::Identity());
  fcl::DistanceRequestd request(/*enable_nearest_points=*/true);
  // libccd's GJK here: FCL's own distance is off by micrometres (tested); the hang of the
  // intersection test (below) is in libccd's MPR, which a distance query does not use.
  request.gjk_solver_type = fcl::GJKSolverType::GST_LIBCCD;
  fcl::DistanceResultd result;
  // Mesh first: FCL then reports the triangle in b1 and the mesh's point first.
  fcl::distance(&surface, &tool, request, result);
  CapsuleSurfaceDistance out;
  out.distance_m = std::max(0.0, result.min_distance);
  out.isColliding = result.min_distance <= 0.0;
  out.pointOnSurface_m = result.nearest_points[0];
  out.pointOnCapsule_m = result.nearest_points[1];
  out.triangle = result.b1;
  return out;
}

void SurfaceBvh::touchedTriangles(const Capsule& capsule, std::vector<int>& triangles) const {
  triangles.clear();
  if (!m_impl->capsule || m_impl->capsule->radius != capsule.radius_m ||
      m_impl->capsule->lz != capsule.length_m) {
    m_impl->capsule = std::make_unique<fcl::Capsuled>(capsule.radius_m, capsule.length_m);
  }
  // fcl::collide copies an AABB model on every call (it does so for every BV type but the
  // oriented ones); driving the traversal ourselves, with the mesh at identity, avoids that.
  CapsuleTriangleTraversal node;
  fcl::Transform3d identity = fcl::Transform3d::Identity();
  const fcl::CollisionRequestd request(static_cast<std::size_t>(m_impl->triangleCount), false);
  m_impl->result.clear();
  fcl::detail::initialize(node, *m_impl->model, identity, *m_impl->capsule, capsule.pose,
                          &m_impl->solver, request, m_impl->result);
  const Eigen::Vector3d halfAxis = capsule.pose.linear().col(2) * (0.5 * capsule.length_m);
  node.axisStart_m = capsule.pose.translation() - halfAxis;
  node.axisEnd_m = capsule.pose.translation() + halfAxis;
  node.radius_m = capsule.radius_m;
  node.touched = &triangles;
  fcl::detail::collide(&node);  // the triangles in traversal order, as FCL's contacts came
}

int SurfaceBvh::vertexCount() const { return m_impl->vertexCount; }
int SurfaceBvh::triangleCount() const { return m_impl->triangleCount; }

}  // namespace tissuesim
