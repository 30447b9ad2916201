#pragma once
// The mechanical system the integrators advance: lumped masses M (kg), internal forces of the
// spring network and the optional volume term, gravity, penalty contacts (the instrument's, the
// tray's, the grasp's springs: evaluated at every trial state, with their stiffness in K),
// constant external forces set by the caller (none in the simulator) and fixed degrees of freedom
// (clamps and prescribed motion: a fixed DOF keeps whatever value the caller puts in the state).
//
//   f(x) = f_springs(x) + f_volume(x) + f_contacts(x) + M g + f_ext                      (N)
//   K(x) = -df/dx, PSD-projected per spring, Gauss-Newton per tet, exact for contacts  (N/m)
//
// Newton's matrix-free operator reads K as its parts' linearisations (SystemLinearization: the
// springs' axial blocks and the volume term's rank-one tets) and the contacts' rank-one terms;
// Cholesky reads it assembled.
//
// Forces on fixed DOFs are zeroed; so are their rows and columns of K (identity diagonal).

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "integrators/PenaltyContacts.h"
#include "numerics/NodeBlockMatrix.h"
#include "springs/SpringForceField.h"
#include "springs/VolumeForceField.h"

namespace tissuesim {

/// Positions (m) and velocities (m/s), each 3 by #V.
struct MechanicalState {
  Eigen::Matrix3Xd x;
  Eigen::Matrix3Xd v;
  bool isFinite() const { return x.allFinite() && v.allFinite(); }
};

struct ForceReport {
  SpringFieldReport springs;
  VolumeFieldReport volume;
};

/// K at one state, as the matrix-free operator reads it: the springs' blocks (5 by #S) and the
/// volume term's (13 by #T; no columns without the term).
struct SystemLinearization {
  AxialBlocks springs;
  VolumeBlocks volume;
};

class MechanicalSystem {
 public:
  /// `springs` (and `volume` when given) must outlive this object.
  MechanicalSystem(SpringForceField& springs, const VolumeForceField* volume);

  const SpringMesh& mesh() const { return m_springs.mesh(); }
  SpringForceField& springs() { return m_springs; }
  const SpringForceField& springs() const { return m_springs; }
  const VolumeForceField* volume() const { return m_volume; }

  MechanicalState restState() const;

  // Constraints.
  void fixNode(int node);
  void fixDof(int node, int axis);
  void releaseAll();
  const std::vector<char>& fixedDofs() const { return m_isFixed; }
  bool isFixed(int node, int axis) const {
    return m_isFixed[static_cast<std::size_t>(3 * node + axis)] != 0;
  }
  /// Incremented whenever the fixed set changes (solvers refactor what depends on it).
  int constraintRevision() const { return m_constraintRevision; }

  Eigen::Vector3d gravity_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Matrix3Xd externalForces_N;  ///< 3 by #V, zero unless a caller sets it
  PenaltyContactSet contacts;         ///< empty unless a caller sets them (each step)

  /// f (3 by #V) overwritten with the total force at x.
  ForceReport forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f) const;
  /// The same, with nodeStiffness (#V) = sum of ||K_e|| per node (explicit stability bound),
  /// and without the contacts: the explicit integrator applies them itself, as impulses.
  ForceReport forcesAndNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                     Eigen::VectorXd& nodeStiffness) const;
  /// The same, and K (made by makeMatrix()) overwritten with the internal stiffness (fixed DOFs not
  /// yet applied): PSD-projected per spring when `isProjected`, else the springs' exact Hessian.
  ForceReport forcesAndStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                 NodeBlockMatrix& stiffness, bool isProjected = true) const;
  /// f, and K's springs and volume term into `linearization` (sized by makeLinearization()), in
  /// one pass each: what the matrix-free SpringSystemOperator reads. The contacts' stiffness is
  /// left to the caller (contacts.rankOneTerms).
  ForceReport forcesAndLinearization(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                     SystemLinearization& linearization,
                                     bool isProjected = true) const;
  SystemLinearization makeLinearization() const;

  /// A matrix with this system's pattern (springs' edges plus diagonal).
  NodeBlockMatrix makeMatrix() const { return NodeBlockMatrix(mesh().nodeCount(), mesh().springs); }

  /// Total energy (J) at a state: kinetic + gravitational + elastic (springs without softening
  /// and the volume term); for checks of energy behaviour, not for the step loop.
  double totalEnergy(const MechanicalState& state) const;

 private:
  void addExternalAndZeroFixed(const Eigen::Matrix3Xd* x, Eigen::Matrix3Xd& f) const;

  SpringForceField& m_springs;
  const VolumeForceField* m_volume;
  std::vector<char> m_isFixed;
  int m_constraintRevision = 0;
  mutable AxialBlocks m_springBlocks;
  mutable VolumeBlocks m_volumeBlocks;
};

}  // namespace tissuesim
