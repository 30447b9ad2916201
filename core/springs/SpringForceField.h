// SPDX-License-Identifier: Apache-2.0
#pragma once
// Mesh-level loops over the springs: forces, stiffness blocks, the explicit stability bound and
// the per-spring Mullins state. The per-spring kernels are SpringForceLaw's; this class only
// gathers positions, scatters forces and keeps the state.
//
// For spring (a, b) with n = (x_b - x_a) / L, lambda = L / L0 and P = P(lambda):
//   F_a = +(V_e / L0) P n,  F_b = -F_a                                                 (N)
//   K_e = (V_e / L0^2) P' n n^T + (V_e P / (L0 L)) (I - n n^T)                        (N/m)
// and the energy Hessian has blocks [K_e, -K_e; -K_e, K_e] on (a, b). Both coefficients are
// clamped at zero (the PSD projection of a spring's Hessian), so assembled matrices stay
// positive semi-definite in compression and on softening branches.

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "numerics/AxialBlocks.h"
#include "parallel/ForkJoinPool.h"

#include "springs/SpringForceLaw.h"
#include "springs/SpringMesh.h"
#include "springs/SpringStiffnessProduct.h"

namespace tissuesim {

/// Parallel passes: the springs are cut into kSpringParts contiguous ranges, each summed into
/// its own force buffer (over the nodes its springs touch), and the buffers are added in part
/// order, node range by node range. The partitions do not depend on the thread count, so
/// results are bit-identical with 1, 2 or 4 threads.
class SpringForceField final : public ForceField {
 public:
  static constexpr int kSpringParts = 4;

  /// Both must outlive this object.
  SpringForceField(const SpringMesh& mesh, const SpringForceLaw& law);
  ~SpringForceField() override;

  /// Runs the spring passes on `pool` (which must outlive this object), or on the calling
  /// thread when null (the default). Not thread-safe itself: one caller at a time.
  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }
  /// The pool set above (null: none); the implicit solvers run their linear solves on it too.
  ForkJoinPool* threadPool() const { return m_pool; }

  /// forces (3 by #V, N) += spring forces at positions x (3 by #V, m).
  SpringFieldReport addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces) const;

  /// The same, and blocks (5 by #S: K_e per spring as (n, axial - lateral, lateral), N/m;
  /// numerics/AxialBlocks.h) overwritten: the PSD projection when `isProjected`, else the exact
  /// Hessian (which may be indefinite). A collapsed spring's block is zero.
  SpringFieldReport addForcesAndStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                          AxialBlocks& blocks, bool isProjected = true) const;

  /// The same, and nodeStiffness (#V, N/m) overwritten with sum_e ||K_e|| over each node's
  /// springs: what the explicit integrator's stability bound needs, in the same pass.
  SpringFieldReport addForcesAndNodeStiffness(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                              Eigen::VectorXd& nodeStiffness) const;

  /// An upper bound on the squared highest angular frequency of the linearised network at x
  /// (1/s^2), from Gershgorin: max over nodes of (2 / m_i) sum_e ||K_e||. The explicit
  /// integrator is stable for dt < 2 / sqrt(this). Allocates scratch: for set-up and reports.
  double frequencySquaredBound(const Eigen::Matrix3Xd& x) const;

  /// Records the current stretches in the Mullins state (lambda_max only grows). Call once per
  /// converged step, not inside solver iterations. When the last addForces() or
  /// addForcesAndStiffness() pass ran at these very positions (bit for bit; an implicit
  /// solver's last pass did), its stretches are taken instead of computed again: the same
  /// numbers, one scan instead of a spring pass.
  void commitStretchHistory(const Eigen::Matrix3Xd& x);
  void resetStretchHistory();
  /// The Mullins memory as a whole (#S peaks), to put back later: a saved state's.
  const std::vector<SofteningPeak>& stretchHistory() const { return m_peaks; }
  /// Puts back a memory taken from stretchHistory() of this field (same spring count).
  void restoreStretchHistory(const std::vector<SofteningPeak>& peaks);
  /// lambda_max per spring (#S), 1 when never stretched.
  const Eigen::VectorXd& lambdaMax() const { return m_lambdaMax; }

  const SpringMesh& mesh() const { return m_mesh; }
  const SpringForceLaw& law() const { return m_law; }

  /// Whether the passes evaluate the law four springs at a time (SpringStressBatch.h): on by
  /// default for the eesm law where the CPU has AVX and FMA. Off, or unavailable, the scalar
  /// law; the two agree to about 1e-15 relative, not to the bit. Returns whether it is on now.
  bool setBatched(bool isBatched);

  // ForceField. K: the blocks above, projected or exact as the pass asks.
  const char* name() const override { return "springs"; }
  /// sum_e V_e W(lambda_e), W the integral of the virgin law's stress from 1 (J): Simpson's rule,
  /// 16 panels a spring. Without softening (an unloading branch has no energy of its own).
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const override {
    if (!m_isInert) SpringStiffnessProduct::addWork(m_mesh, nodeWork);
  }
  void prepareProducts(const PartBounds& bounds) override;
  void addStiffnessProduct(int part, const double* x, double* y) const override {
    if (!m_isInert) m_product->addPart(part, currentBlocks(), x, y);
  }
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override {
    if (!m_isInert) m_product->addDiagonalBlock(j, currentBlocks(), block);
  }
  /// Whether every spring's V_e is zero (the FEM's network, kept for its stretches and the
  /// grasp): then its forces and K are zero, and the passes, products and assembly skip them.
  bool isInert() const { return m_isInert; }
  void addStiffness(NodeBlockMatrix& matrix) const override;

 private:
  const AxialBlocks& currentBlocks() const { return m_slots[static_cast<std::size_t>(m_current)]; }

  template <bool withBlocks, bool withNodeStiffness>
  SpringFieldReport accumulate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                               AxialBlocks* blocks, Eigen::VectorXd* nodeStiffness,
                               bool isProjected) const;
  /// Springs [begin, end) into forces and nodeStiffness (both added to).
  template <bool withBlocks, bool withNodeStiffness>
  SpringFieldReport accumulateRange(Eigen::Index begin, Eigen::Index end, const Eigen::Matrix3Xd& x,
                                    Eigen::Matrix3Xd& forces, AxialBlocks* blocks,
                                    Eigen::VectorXd* nodeStiffness, bool isProjected) const;

  /// The same, the law taken four springs at a time where it can be (SpringStressBatch.h).
  template <bool withBlocks, bool withNodeStiffness>
  SpringFieldReport accumulateRangeBatched(Eigen::Index begin, Eigen::Index end,
                                           const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                                           AxialBlocks* blocks, Eigen::VectorXd* nodeStiffness,
                                           bool isProjected) const;
  /// Spring s's force (and stiffness) from its stress P and slope (Pa) at the stretch
  /// lambda = length / L0 of d = x_b - x_a: what every pass does after the law.
  template <bool withBlocks, bool withNodeStiffness>
  void applyStress(Eigen::Index s, int a, int b, const Eigen::Vector3d& d, double length,
                   double stress, double slope, Eigen::Matrix3Xd& forces, AxialBlocks* blocks,
                   Eigen::VectorXd* nodeStiffness, bool isProjected) const;

  /// First spring of part p of the parallel passes (p = kSpringParts: the spring count).
  Eigen::Index partStart(int p) const { return m_mesh.springCount() * p / kSpringParts; }

  const SpringMesh& m_mesh;
  const SpringForceLaw& m_law;
  Eigen::VectorXd m_inverseRestLength;  ///< #S, 1 / L0 (1/m)
  Eigen::VectorXd m_areaOverLength;     ///< #S, V_e / L0 (m^2)
  std::vector<SofteningPeak> m_peaks;   ///< #S: lambda_max and what softening derives from it
  /// #S: the peaks' lambda_max again, contiguous: the commit reads only these (42 kB at 5k
  /// springs, not the 250 kB of the peaks).
  Eigen::VectorXd m_lambdaMax;
  ForkJoinPool* m_pool = nullptr;
  bool m_isBatched = false;
  // What the last pass saw: its positions and every spring's stretch, for the commit. Mutable:
  // a record of the const passes, sized at construction (assigning x of the same size does not
  // allocate).
  mutable Eigen::Matrix3Xd m_passPositions;
  mutable Eigen::VectorXd m_passStretch;  ///< #S
  // Per-part scratch of the parallel passes (part 0 adds into the caller's arrays). Mutable:
  // scratch only, sized at construction, so the const passes never allocate.
  mutable std::array<Eigen::Matrix3Xd, kSpringParts - 1> m_partForces;
  mutable std::array<Eigen::VectorXd, kSpringParts - 1> m_partNodeStiffness;
  /// The nodes [begin, end) that part p's springs touch: what its buffer clears and adds.
  struct NodeSpan {
    Eigen::Index begin = 0;
    Eigen::Index end = 0;
    Eigen::Index size() const { return end - begin; }
  };
  std::array<NodeSpan, kSpringParts> m_partNodes;
  // The stiffness slots (ForceField.h): the current one is m_slots[m_current]. Mutable: scratch
  // of the const passes, sized at construction.
  mutable std::array<AxialBlocks, 2> m_slots;
  mutable int m_current = 0;
  std::unique_ptr<SpringStiffnessProduct> m_product;  ///< prepareProducts()'s
  bool m_isInert = false;
};

}  // namespace tissuesim
