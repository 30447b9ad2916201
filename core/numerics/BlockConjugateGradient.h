// SPDX-License-Identifier: Apache-2.0
#pragma once
// Block-Jacobi-preconditioned conjugate gradients on a symmetric positive definite
// BlockLinearOperator (the assembled NodeBlockMatrix, or the springs' matrix-free operator):
//
//   A x = b,   A: 3#V by 3#V (N/m),  b: 3#V (N),  x: 3#V (m), started from x = 0
//
// or from the x given (a warm start: a time step's Newton step is close to the one before it
// while the tissue moves smoothly, so CG starts from most of the answer),
// stopping when ||b - A x||_2 <= tolerance ||b||_2 (Eigen's ConjugateGradient criterion) or after
// maxIterations. Why not Eigen's: its product is a serial scalar CSC loop that reads one row index
// per value; here the product is the operator's own (one neighbour index per 3x3 block, or none at
// all), and every pass (product, updates, dot products) runs over the operator's kParts fixed node
// ranges, on a ForkJoinPool when one is set. The ranges and the order in which their partial dot
// products are summed do not depend on the thread count, so the result is bit-identical with 1, 2
// or 4 threads. The preconditioner is the inverse of each node's 3x3 diagonal block, not of its
// diagonal entries: an instrument contact adds k w^2 n n^T there, along a normal that is rarely an
// axis, and the springs' blocks couple the axes too. On the held probe it takes 9.5 products a step
// against 10.8 with scalar Jacobi, on the stretched slab 14-15 against 19.
//
// Rank-one terms (instrument contacts): A may hold terms k u u^T whose u spans up to three
// nodes (RankOneTerm). Block Jacobi sees only their diagonal blocks, not the coupling between
// a contact triangle's corners, and a contact's penalty (10^4 N/m) is several times a surface
// node's own mass-and-spring block. Told of the terms, the preconditioner becomes
//   M = B + U K U^T,   B = blockdiag(A) - blockdiag(U K U^T)   (U: 3#V by C, K = diag(k_c))
// applied with the Woodbury identity
//   M^-1 r = B^-1 r - W S^-1 W^T r,   W = B^-1 U,   S = K^-1 + U^T B^-1 U   (C by C, SPD)
// so the contacts are inverted exactly at the cost of a C by C Cholesky factorisation a solve
// and O(C^2) a iteration, on the calling thread. Above kMaxExactTerms terms (a probe pressed flat
// into the surface), or with a term it cannot take (k <= 0, not finite), it falls back to plain
// block Jacobi. On the held probe (1-3 contacts) it takes 8.7 products a step against 9.7; the
// rest of the gap to the free slab's 4.7 is the liver mesh's, not the contacts'.
// No allocation once the scratch is sized for a matrix (the first solve, or a new size).

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "numerics/BlockLinearOperator.h"
#include "numerics/RankOneTerm.h"
#include "numerics/RankOneTermDiagonals.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

struct ConjugateGradientReport {
  int iterations = 0;  ///< products A p, the last one included (Eigen's count is one fewer)
  double relativeResidual = 0.0;  ///< ||b - A x|| / ||b|| at the end (0 when b = 0)
  bool converged = false;
};

class BlockConjugateGradient {
 public:
  static constexpr int kParts = BlockLinearOperator::kParts;
  /// The most rank-one terms the preconditioner inverts exactly (a 64 by 64 factorisation).
  static constexpr int kMaxExactTerms = 64;

  /// Runs the passes on `pool` (which must outlive its use here), or on the caller when null.
  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }

  /// Solves A x = b; x is resized to b's size if needed and overwritten. `terms` (optional):
  /// rank-one terms that A contains, for the preconditioner (see above); each u must be zero on
  /// the DOFs whose rows and columns A has replaced by the identity (fixed DOFs).
  /// With `isWarm`, x (when finite and of b's size) is the starting guess, else 0.
  ConjugateGradientReport solve(const BlockLinearOperator& a, const Eigen::VectorXd& b,
                                Eigen::VectorXd& x, double tolerance, int maxIterations,
                                std::span<const RankOneTerm> terms = {}, bool isWarm = false);

 private:
  void resize(const BlockLinearOperator& a);
  /// Lists the terms' nodes and the diagonal blocks they add (m_termDiagonals), for B; false
  /// (no exact terms this solve) when there are none or more than kMaxExactTerms.
  bool listTerms(std::span<const RankOneTerm> terms);
  /// W = B^-1 U and the factor of S, once B's inverse blocks are stored; false when S is not
  /// positive definite (then plain block Jacobi is used).
  bool factorCapacitance(std::span<const RankOneTerm> terms);
  /// z -= W S^-1 U^T z on the terms' nodes (z = B^-1 r before), and the same on `alsoP` when
  /// given; returns (U^T z) . (S^-1 U^T z), the amount r . z drops by.
  double correctForTerms(std::span<const RankOneTerm> terms, double* z, double* alsoP);
  void clearTerms();
  /// Calls pass(part, firstNode, lastNode) for every part, in parallel when a pool is set.
  template <typename Pass>
  void forEachPart(Pass& pass);

  ForkJoinPool* m_pool = nullptr;
  Eigen::Index m_nodeCount = -1;
  BlockLinearOperator::PartBounds m_bounds{};  ///< the operator's node ranges
  Eigen::VectorXd m_inverseBlocks;  ///< 6#V: per node, the upper triangle of its block's inverse
  Eigen::VectorXd m_r, m_z, m_p, m_q;
  std::array<double, kParts> m_dotA{}, m_dotB{}, m_dotC{};  ///< per-part partial dot products
  // The rank-one terms' scratch (sized once, in resize()).
  RankOneTermDiagonals m_termDiagonals;  ///< the terms' diagonal blocks, for B
  std::vector<std::array<Eigen::Vector3d, kMaxTermNodes>> m_termW;  ///< per term, W at its nodes
  Eigen::MatrixXd m_capacitance;  ///< kMaxExactTerms square; S's Cholesky factor in its corner
  Eigen::VectorXd m_termT, m_termSolved;  ///< kMaxExactTerms each: U^T z and S^-1 U^T z
};

}  // namespace tissuesim
