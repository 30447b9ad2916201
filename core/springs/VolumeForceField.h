#pragma once
// The optional near-incompressibility term, per tet (off unless a scene asks for it):
//
//   E_t = 1/2 kappa V0 (J - 1)^2,   J = V / V0,   V = (x_b - x_a) . ((x_c - x_a) x (x_d - x_a)) / 6
//   f_i = -kappa (J - 1) dV/dx_i                                                         (N)
//   H  ~= (kappa / V0) g g^T,  g = dV/dx (12)   (Gauss-Newton: the PSD part of the Hessian)
//
// kappa (Pa) is a bulk modulus. It resists volume change, pushes an inverted tet (J < 0) back
// out, and gives the spring network the lateral contraction it otherwise lacks.

#include <Eigen/Core>

#include "parallel/ForkJoinPool.h"
#include "springs/SpringMesh.h"

namespace tissuesim {

struct VolumeFieldReport {
  int invertedTetCount = 0;  ///< J <= 0
  double minVolumeRatio = 1.0;
};

class VolumeForceField {
 public:
  /// @param bulkModulus_Pa kappa > 0. `mesh` must outlive this object.
  VolumeForceField(const SpringMesh& mesh, double bulkModulus_Pa);

  /// forces (3 by #V) += volume forces at x; blocks (144 by #T, column-major 12x12) overwritten
  /// when not null.
  VolumeFieldReport addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                              Eigen::Matrix<double, 144, Eigen::Dynamic>* blocks) const;

  /// Counts tets with J <= 0 at x without computing forces; in kInspectParts tet ranges on
  /// `pool` when given (the report is the same: a count and a minimum).
  static VolumeFieldReport inspect(const SpringMesh& mesh, const Eigen::Matrix3Xd& x,
                                   ForkJoinPool* pool = nullptr);
  static constexpr int kInspectParts = 4;

  double bulkModulus() const { return m_bulkModulus_Pa; }
  /// Upper bound of the term's contribution to ||K|| per node (N/m), for the explicit bound.
  double stiffnessBound(Eigen::Index tet, const Eigen::Matrix3Xd& x) const;

 private:
  const SpringMesh& m_mesh;
  double m_bulkModulus_Pa;
};

}  // namespace tissuesim
