#pragma once
// Block-Jacobi-preconditioned conjugate gradients on a symmetric positive definite
// NodeBlockMatrix:
//
//   A x = b,   A: 3#V by 3#V (N/m),  b: 3#V (N),  x: 3#V (m), started from x = 0
//
// stopping when ||b - A x||_2 <= tolerance ||b||_2 (Eigen's ConjugateGradient criterion) or
// after maxIterations. Why not Eigen's: its product is a serial scalar CSC loop that reads one
// row index per value; here the product reads one neighbour index per 3x3 block, and every pass
// (product, updates, dot products) runs over kParts fixed node ranges, on a ForkJoinPool when
// one is set. The ranges and the order in which their partial dot products are summed do not
// depend on the thread count, so the result is bit-identical with 1, 2 or 4 threads.
// The preconditioner is the inverse of each node's 3x3 diagonal block, not of its diagonal
// entries: an instrument contact adds k w^2 n n^T there, along a normal that is rarely an axis,
// and the springs' blocks couple the axes too. On the held probe it takes 9.5 products a step
// against 10.8 with scalar Jacobi, on the stretched slab 14-15 against 19.
// No allocation once the scratch is sized for a matrix (the first solve, or a new size).

#include <array>

#include <Eigen/Core>

#include "numerics/NodeBlockMatrix.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

struct ConjugateGradientReport {
  int iterations = 0;  ///< products A p, the last one included (Eigen's count is one fewer)
  double relativeResidual = 0.0;  ///< ||b - A x|| / ||b|| at the end (0 when b = 0)
  bool converged = false;
};

class BlockConjugateGradient {
 public:
  static constexpr int kParts = 4;

  /// Runs the passes on `pool` (which must outlive its use here), or on the caller when null.
  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }

  /// Solves A x = b; x is resized to b's size if needed and overwritten.
  ConjugateGradientReport solve(const NodeBlockMatrix& a, const Eigen::VectorXd& b,
                                Eigen::VectorXd& x, double tolerance, int maxIterations);

 private:
  void resize(const NodeBlockMatrix& a);
  /// Calls pass(part, firstNode, lastNode) for every part, in parallel when a pool is set.
  template <typename Pass>
  void forEachPart(Pass& pass);

  ForkJoinPool* m_pool = nullptr;
  Eigen::Index m_nodeCount = -1;
  std::array<Eigen::Index, kParts + 1> m_bounds{};  ///< node ranges of about equal stored values
  Eigen::VectorXd m_inverseBlocks;  ///< 6#V: per node, the upper triangle of its block's inverse
  Eigen::VectorXd m_r, m_z, m_p, m_q;
  std::array<double, kParts> m_dotA{}, m_dotB{};  ///< per-part partial dot products
};

}  // namespace tissuesim
