#pragma once
// Contact between the rigid probe (a capsule: shaft of radius r ending in a hemispherical blunt
// tip) and the deforming tissue, for the engine's ContactProvider.
//
// Detection: an FCL AABB hierarchy over the tet mesh's boundary triangles, refitted to the
// current positions every step (never rebuilt), collided with the capsule fattened by half a
// radius (FCL's own GJK: libccd's MPR can hang, SurfaceBvh.cpp) to find the triangles it
// touches or is about to touch.
//
// Response: one penalty contact (PenaltyContacts.h) per such triangle, frozen for the step: the
// triangle's point p nearest the capsule's axis (c on the axis; exact segment-triangle closest
// points) must stay at least r from c along u = (p - c) / |p - c|, the way the capsule's surface
// faces there, with stiffness k. At the tip that is the face's inward normal (the tip carries the
// face ahead of it); beside the shaft it is radial (the shaft holds the dent's walls apart).
// Taking the direction from the capsule, not from the face's normal, matters once the tool is
// deep: with the face normal, a face the shaft had passed was pushed along the shaft and the
// surface closed over the tool. A face the axis runs through is pushed ahead of the tip when it
// lies across the tool, radially off the axis when it lies along it.
// The integrators evaluate the contacts at their trial states; the implicit ones carry k in the
// Newton matrix, so it can be stiff: 10^4 N/m per face (a 1.7 N push over one face penetrates
// 0.17 mm). It used to be an explicit force, capped near 1,000 N/m by stability; at 300 N/m the
// 2.5 mm tip sank 4.8 mm below the surface. The explicit integrator applies the contacts as
// impulses, each stepped by backward Euler (with damping c, which symplectic Euler lacks).
// Tunnelling: the tool moves 0.5 mm a step at 0.5 m/s, a fifth of its radius, so a triangle is
// always caught before it could pass the tip.

#include <memory>

#include "SurfaceBvh.h"
#include "mesh/TetMesh.h"
#include "sim/ContactProvider.h"

namespace tissuesim {

struct CapsuleContactSettings {
  double radius_m = 0.0025;
  double length_m = 0.3;
  double stiffness_N_m = 1e4;  ///< penalty k per triangle
  double damping_N_s_m = 6.0;  ///< c per triangle, explicit integrator only (PenaltyContacts.h)
};

class CapsuleContact final : public ContactProvider {
 public:
  /// @param mesh the tet mesh at rest (its boundary faces are what the tool can touch).
  CapsuleContact(const TetMesh& mesh, CapsuleContactSettings settings);
  ~CapsuleContact() override;

  void findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                    PenaltyContactSet& contacts) override;

  Eigen::Index boundaryTriangleCount() const { return m_faces.cols(); }

 private:
  CapsuleContactSettings m_settings;
  Eigen::Matrix3Xi m_faces;         ///< boundary faces, local vertex indices
  std::vector<int> m_surfaceNodes;  ///< local index -> mesh node
  Eigen::MatrixX3d m_vertices;      ///< #local by 3 scratch for refits
  std::unique_ptr<SurfaceBvh> m_bvh;
  std::vector<int> m_touched;  ///< scratch: local vertices of touched triangles
  std::vector<char> m_isTouched;
};

}  // namespace tissuesim
