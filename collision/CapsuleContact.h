// SPDX-License-Identifier: Apache-2.0
#pragma once
// Contact between the rigid probe (a capsule: shaft of radius r ending in a hemispherical blunt
// tip) and the deforming tissue, for the engine's ContactProvider.
//
// The surface the tool touches is the one the trainee sees: the embedded visual surface
// (SurfaceEmbedding), moved by the tet mesh, when the scene has one; else the tet mesh's own
// boundary. The visual surface lies millimetres off the lattice's boundary (on the bundled
// 5,300-spring liver 2.2 mm mean, 7.5 mm at most), so a tool colliding with the boundary sank
// visibly into the drawn liver or stopped short of it.
//
// Detection: an FCL AABB hierarchy over that surface's triangles, refitted to the current
// positions every step (never rebuilt), collided with the capsule fattened by half a radius
// (FCL's own GJK: libccd's MPR can hang, SurfaceBvh.cpp) to find the triangles it touches or is
// about to touch.
//
// Response near the tip: one penalty contact (PenaltyContacts.h) per such triangle, frozen for
// the step: the triangle's point p nearest the capsule's axis (c on the axis; exact
// segment-triangle closest points) must stay at least r from c along u = (p - c) / |p - c|, the way
// the capsule's surface faces there, with stiffness k. Where p lies on an edge or at a corner, the
// faces that share it find the same point: it is one contact, the first face's. Counted once per
// face, a corner pushed back with its valence times k, and which faces shared the point changed
// from one step to the next: a probe held deep never settled (every step started newtons out of
// balance). At the tip that is the face's inward normal (the tip carries the face ahead of it);
// beside the shaft it is radial (the shaft holds the dent's walls apart). Taking the direction from
// the capsule, not from the face's normal, matters once the tool is deep: with the face normal, a
// face the shaft had passed was pushed along the shaft and the surface closed over the tool. A face
// the axis runs through is pushed ahead of the tip when it lies across the tool, radially off the
// axis when it lies along it.
// The shaft holds a face at fixed points instead: four inside it (its centroid and one towards
// each corner), each pushed radially off the axis with k. A face lying along the shaft has no
// well-determined nearest point: it jumped between the face's edges from one step to the next,
// merging with a neighbour's point and parting again, and a probe held deep cycled so (the
// contact set and the force changing every step). Fixed points enter and leave the capsule
// where their force is zero. Each takes the whole k: at a quarter (a face's k shared out) or a
// half, the tissue slipped through a shaft swept sideways deep in it. A face changes from the
// tip's rule to the shaft's as its centroid rises from the tip's centre to a radius above it (a
// smoothstep sharing k between them), by where the face lies, not by its nearest point, which
// jumps the same way.
// The integrators evaluate the contacts at their trial states; the implicit ones
// carry k in the Newton matrix, so it can be stiff: 10^4 N/m per face (a 1.7 N push over one face
// penetrates 0.17 mm). It used to be an explicit force, capped near 1,000 N/m by stability; at 300
// N/m the 2.5 mm tip sank 4.8 mm below the surface. The explicit integrator applies the contacts as
// impulses, each stepped by backward Euler (with damping c, which symplectic Euler lacks).
// Tunnelling: the tool moves 0.5 mm a step at 0.5 m/s, a fifth of its radius, so a triangle is
// always caught before it could pass the tip.
// Where the force goes: on the visual surface, each drawn triangle is carried by the tet that
// holds its centroid at rest (TetLocator, at construction), and a contact at the triangle's
// point p acts on s(x) = sum_k w_k x_k over that tet's four nodes, w the rest point's
// barycentric weights there (clamped to the tet where the surface lies outside it): the force
// reaches the nodes through the transpose of the interpolation that moves the drawn surface, as
// SOFA's mapped collision models apply it, and the contact stays rank one over four nodes that
// springs join (the implicit solve's terms). The step's penetration is the drawn point's own:
// the gap p - s(x) at the step's start is frozen into the contact's offset. On the boundary,
// s(x) is the triangle's own point over its three corners.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "collision/SurfaceBvh.h"
#include "forces/ContactProvider.h"
#include "mesh/SurfaceEmbedding.h"
#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"
#include "sim/Simulation.h"

namespace tissuesim {

struct CapsuleContactSettings {
  double radius_m = 0.0025;
  double length_m = 0.3;
  double stiffness_N_m = 1e4;  ///< penalty k per triangle
  double damping_N_s_m = 6.0;  ///< c per triangle, explicit integrator only (PenaltyContacts.h)
};

class CapsuleContact final : public ContactProvider {
 public:
  /// Contact with the tet mesh's boundary. @param mesh the tet mesh at rest.
  CapsuleContact(const TetMesh& mesh, CapsuleContactSettings settings);
  /// Contact with the drawn surface `visual` (at rest, welded), embedded in `mesh` by
  /// `embedding`; all three must outlive this object.
  CapsuleContact(const TetMesh& mesh, const TriangleSurface& visual,
                 const SurfaceEmbedding& embedding, CapsuleContactSettings settings);
  ~CapsuleContact() override;

  void findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                    PenaltyContactSet& contacts) override;

  /// The triangles the tool can touch (the drawn surface's, or the boundary's).
  Eigen::Index boundaryTriangleCount() const { return m_faces.cols(); }
  bool isOnVisualSurface() const { return m_embedding != nullptr; }

 private:
  void buildBvh(const Eigen::MatrixX3d& restVertices);
  /// The nodes and weights that carry the point with weights `onTriangle` on face f.
  void carry(Eigen::Index f, const Eigen::Vector3d& onTriangle, PenaltyContact& contact) const;

  CapsuleContactSettings m_settings;
  Eigen::Matrix3Xi m_faces;  ///< the touchable faces, local vertex indices
  // The boundary: local index -> mesh node.
  std::vector<int> m_surfaceNodes;
  // The drawn surface: its embedding, and per face the tet that carries it: the tet's nodes and
  // the face's three corners' barycentric weights in it at rest (a column each). A point with
  // weights b on the face has weights W b in the tet: barycentric coordinates are affine.
  struct FaceCarrier {
    std::array<int, kMaxTermNodes> nodes{};
    Eigen::Matrix<double, 4, 3> cornerWeights = Eigen::Matrix<double, 4, 3>::Zero();
  };
  const SurfaceEmbedding* m_embedding = nullptr;
  std::vector<FaceCarrier> m_carriers;
  Eigen::MatrixX3d m_vertices;  ///< #local by 3 scratch for refits
  std::unique_ptr<SurfaceBvh> m_bvh;
  /// Whether face f's nearest point, at barycentric `weights`, is the first this pass at its
  /// place on the surface: inside the face always; on an edge or at a corner, the first face
  /// there (the edge or corner joins it to the step's list).
  bool isFirstAtFeature(Eigen::Index f, const Eigen::Vector3d& weights);

  std::vector<int> m_touched;  ///< scratch: the touched triangles
  /// scratch: the edges (corner pairs) and corners (a corner twice) that hold a contact
  std::vector<std::uint64_t> m_features;
};

/// The instrument's contact for a simulation's scene (which must have an instrument): on the drawn
/// surface when the scene has one, else on the tet mesh's boundary. `simulation` must outlive it.
std::unique_ptr<CapsuleContact> makeInstrumentContact(const Simulation& simulation);

}  // namespace tissuesim
