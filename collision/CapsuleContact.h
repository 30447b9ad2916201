#pragma once
// Contact between the rigid probe (a capsule: shaft of radius r ending in a hemispherical blunt
// tip) and the deforming tissue, for the engine's ContactProvider.
//
// Detection: an FCL OBBRSS hierarchy over the tet mesh's boundary triangles, refitted to the
// current positions every step (never rebuilt), collided with the capsule (libccd's GJK/EPA
// where FCL uses it) to find the triangles it touches.
//
// Response: penalty with damping per touched triangle, along its outward normal n:
//   f = -(k delta + c v.n) n on the tissue, delta = r - (height of the capsule axis above the
//   triangle's plane), spread to the triangle's corners by barycentric weights.
// The penalty is explicit in time, so k is bounded by stability: k dt^2 / m_node < 1. With the
// liver's node masses (~1 g) at 1 ms that allows about 1,000 N/m; we use 300 N/m per triangle,
// so a 1 N push over three or more triangles penetrates about 1 mm (the stated tolerance).
// The reaction on the instrument is minus the sum, and the torque about the tip; that is what a
// haptic device would render. Tunnelling: the tool moves 0.5 mm a step at 0.5 m/s, a fifth of
// its radius, so nodes are always caught inside before they can pass through.

#include <memory>

#include "SurfaceBvh.h"
#include "mesh/TetMesh.h"
#include "sim/ContactProvider.h"

namespace tissuesim {

struct CapsuleContactSettings {
  double radius_m = 0.0025;
  double length_m = 0.3;
  double stiffness_N_m = 300.0;      ///< penalty k per triangle
  double damping_N_s_m = 0.5;        ///< c per triangle
};

class CapsuleContact final : public ContactProvider {
 public:
  /// @param mesh the tet mesh at rest (its boundary faces are what the tool can touch).
  CapsuleContact(const TetMesh& mesh, CapsuleContactSettings settings);
  ~CapsuleContact() override;

  ContactResult addContactForces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                                 const InstrumentPose& pose, Eigen::Matrix3Xd& forces) override;

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
