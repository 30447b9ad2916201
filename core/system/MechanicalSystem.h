// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mechanical system the integrators advance: lumped masses M (kg), the force fields
// (forces/ForceField.h) that make up
//
//   f(x) = f_springs(x) + f_volume(x) + f_contacts(x) + M g + f_ext                      (N)
//   K(x) = -df/dx: each field's, as the pass asks (projected or exact)                 (N/m)
//
// the springs, the optional volume term, the penalty contacts (the instrument's, the tray's,
// the grasp's: set by the caller each step, evaluated at every trial state) and gravity, plus
// constant external forces set by the caller (none in the simulator) and fixed degrees of
// freedom (clamps and prescribed motion: a fixed DOF keeps whatever value the caller puts in the
// state). Forces on fixed DOFs are zeroed; the solvers make their rows and columns of K the
// identity's. Newton reads K through the fields: matrix-free (SystemOperator) or assembled.

#include <vector>

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "forces/GravityForceField.h"
#include "forces/PenaltyContacts.h"
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

class MechanicalSystem {
 public:
  /// `springs` (and `volume` when given) must outlive this object.
  MechanicalSystem(SpringForceField& springs, VolumeForceField* volume);
  MechanicalSystem(const MechanicalSystem&) = delete;
  MechanicalSystem& operator=(const MechanicalSystem&) = delete;

  const SpringMesh& mesh() const { return m_springs.mesh(); }
  SpringForceField& springs() { return m_springs; }
  const SpringForceField& springs() const { return m_springs; }
  const VolumeForceField* volume() const { return m_volume; }
  /// Every field, in the order their forces are summed: springs, volume term, gravity, contacts.
  const std::vector<const ForceField*>& fields() const { return m_fields; }
  /// Adds a field (which must outlive this object), summed before the contacts: a force a test
  /// or a tool brings (CapsulePenalty). Before any solver is prepared on this system.
  void addField(ForceField& field);
  /// Every field's products prepared on these node ranges (SystemOperator's).
  void prepareProducts(const ForceField::PartBounds& bounds);
  /// The thread pool the passes and solves run on (the springs'; null: the caller's thread).
  ForkJoinPool* threadPool() const { return m_springs.threadPool(); }

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

  GravityForceField gravity;          ///< its acceleration_m_s2: zero unless a caller sets it
  PenaltyContactSet contacts;         ///< empty unless a caller sets them (each step)
  Eigen::Matrix3Xd externalForces_N;  ///< 3 by #V, zero unless a caller sets it

  /// f (3 by #V) overwritten with the total force at x; each field keeps K at x where `pass`
  /// asks (its fixedDofs are this system's, whatever the caller put there).
  ForceReport forces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                     const ForcePass& pass = {}) const;
  /// The same, with nodeStiffness (#V) = sum of ||K_e|| per node (explicit stability bound),
  /// and without the contacts: the explicit integrator applies them itself, as impulses.
  ForceReport forcesAndNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f,
                                     Eigen::VectorXd& nodeStiffness) const;
  /// Every field's trial stiffness becomes its current one (a line search's accepted trial).
  void acceptTrialStiffness() const;
  /// `matrix` (made by makeMatrix()) overwritten with K from the fields' current slots (fixed
  /// DOFs not yet applied).
  void assembleStiffness(NodeBlockMatrix& matrix) const;

  /// A matrix with this system's pattern: the springs' edges (first, in order), then the node
  /// pairs its fields couple that no spring joins (ForceField::couplings: a volume cell's, a
  /// nodal volume term's star), plus the diagonal (a contact's nodes are a tet's, joined by
  /// springs).
  NodeBlockMatrix makeMatrix() const;

  /// Total energy (J) at a state: kinetic plus every field's (springs without softening).
  /// For checks of energy behaviour, not for the step loop.
  double totalEnergy(const MechanicalState& state) const;

 private:
  void addExternalAndZeroFixed(Eigen::Matrix3Xd& f) const;

  SpringForceField& m_springs;
  VolumeForceField* m_volume;
  std::vector<const ForceField*> m_fields;
  std::vector<ForceField*> m_mutableFields;  ///< the same, for prepareProducts()
  std::vector<char> m_isFixed;
  int m_constraintRevision = 0;
};

}  // namespace tissuesim
