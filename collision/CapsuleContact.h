#pragma once
// Contact between the rigid probe (a capsule: shaft of radius r ending in a hemispherical blunt
// tip) and the deforming tissue, for the engine's ContactProvider.
//
// Detection: an FCL OBBRSS hierarchy over the tet mesh's boundary triangles, refitted to the
// current positions every step (never rebuilt), collided with the capsule (libccd's GJK/EPA
// where FCL uses it) to find the triangles it touches.
//
// Response: one penalty contact (PenaltyContacts.h) per touched triangle, along its outward
// normal n at the start of the step: the axis point c nearest the triangle's centroid must stay
// at least r above the triangle's plane, so the triangle point s under c (barycentric weights w)
// is held below the plane n . y = n . c - r with stiffness k. The integrator evaluates it at its
// trial states; with the implicit integrators k enters the Newton matrix, so it can be stiff:
// 10^4 N/m per triangle (a 1.7 N push over one triangle penetrates 0.17 mm). It used to be an
// explicit force, capped near 1,000 N/m by stability; at 300 N/m the 2.5 mm tip sank below the
// surface and the surface wrapped the shaft instead of being carried ahead of the tip. The
// explicit integrator substeps for it (its stability bound includes the contacts).
// Triangles within half a radius of touching are added too, inactive until the tissue reaches
// them inside the step. Damping: none in the contact itself; the integrator's mass damping and
// implicit Euler's dissipation take it.
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
  Eigen::Matrix3Xi m_faces;           ///< boundary faces, local vertex indices
  std::vector<int> m_surfaceNodes;    ///< local index -> mesh node
  Eigen::MatrixX3d m_vertices;        ///< #local by 3 scratch for refits
  std::unique_ptr<SurfaceBvh> m_bvh;
  std::vector<int> m_touched;         ///< scratch: local vertices of touched triangles
  std::vector<char> m_isTouched;
};

}  // namespace tissuesim
