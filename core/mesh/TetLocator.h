// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which tet of a mesh holds a point, in the mesh's rest frame, and the point's barycentric
// weights w (4, summing to 1; all >= 0 inside) there, so that the point moves with the mesh as
//
//   p(x) = sum_k w_k x_{t k}                                                       (m)
//
// A point outside every tet gets the tet it is least outside of (its smallest weight the
// largest): the tet's affine motion extrapolated, which still carries rigid motions exactly.
// Tets are binned by bounding box on a grid of about twice the mean tet size; a point is looked
// up in its bin, then the bins around it, then (only if those are empty) every tet.
// The embedded visual surface (SurfaceEmbedding) places its vertices with it, and contact on
// the drawn surface (collision/CapsuleContact) places each contact point with it.

#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

struct TetLocation {
  int tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  bool isInside() const { return weights.minCoeff() >= -1e-12; }
};

/// Barycentric weights clamped to their tet (negative ones set to 0, the rest renormalised): a
/// point of the tet for one outside it, carried without the lever of extrapolated weights.
inline Eigen::Vector4d clampedToTet(const Eigen::Vector4d& weights) {
  const Eigen::Vector4d clamped = weights.cwiseMax(0.0);
  return clamped / clamped.sum();
}

class TetLocator {
 public:
  /// @param mesh at rest; must outlive this object, and have at least one tet.
  explicit TetLocator(const TetMesh& mesh);

  /// The tet holding p (m), or the least outside of the tets near it.
  TetLocation locate(const Eigen::Vector3d& p) const;
  /// p's weights in tet t (rest frame).
  Eigen::Vector4d weightsIn(int t, const Eigen::Vector3d& p) const;
  /// The best of `tets` for p (as locate(), among these only; tets must not be empty).
  TetLocation locateAmong(const std::vector<int>& tets, const Eigen::Vector3d& p) const;
  /// Appends to `tets` the tets whose bins overlap the box [lower, upper] (m), without repeats
  /// of what it appends; tets near the box, not only those that touch it.
  void tetsNear(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                std::vector<int>& tets) const;

  const TetMesh& mesh() const { return m_mesh; }

 private:
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;
  long long keyOf(const Eigen::Vector3i& cell) const;

  const TetMesh& m_mesh;
  /// Per tet, the inverse of its edge matrix [b - a, c - a, d - a] (column-major, 9 doubles).
  std::vector<Eigen::Matrix3d> m_inverseEdges;
  Eigen::Vector3d m_lower;
  double m_cell_m = 1.0;
  Eigen::Vector3i m_cells;
  std::unordered_map<long long, std::vector<int>> m_bins;
};

}  // namespace tissuesim
