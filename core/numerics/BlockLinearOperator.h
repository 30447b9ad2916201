// SPDX-License-Identifier: Apache-2.0
#pragma once
// A symmetric linear operator on 3-vectors per node, y = A x (A: 3#V by 3#V), as conjugate
// gradients needs it: the product in kParts fixed node ranges that may run on different threads
// at once, and the 3x3 diagonal blocks for the preconditioner. Implemented by the assembled
// NodeBlockMatrix and by the matrix-free SystemOperator (system/). The ranges belong
// to the operator (its product's work decides where to cut) and never depend on the thread
// count, so a solve on them is bit-identical with any number of threads.

#include <array>

#include <Eigen/Core>

namespace tissuesim {

class NodeBlockMatrix;

class BlockLinearOperator {
 public:
  static constexpr int kParts = 4;
  using PartBounds = std::array<Eigen::Index, kParts + 1>;

  virtual ~BlockLinearOperator() = default;

  /// #V.
  virtual Eigen::Index nodeCount() const = 0;
  /// Part p's nodes are [bounds[p], bounds[p + 1]); bounds[0] = 0, bounds[kParts] = #V.
  virtual const PartBounds& partBounds() const = 0;
  /// Rows 3j .. 3j+2 of y = A x for part p's nodes j only (x and y: 3#V).
  virtual void multiplyPart(int part, const double* x, double* y) const = 0;
  /// Block (j, j) of A.
  virtual Eigen::Matrix3d diagonalBlock(Eigen::Index j) const = 0;
  /// The (j, j) block conjugate gradients' preconditioner inverts: A's own by default.
  virtual Eigen::Matrix3d preconditionerBlock(Eigen::Index j) const { return diagonalBlock(j); }
  /// A itself when it is stored assembled (what a direct solver factorises), else null.
  virtual const NodeBlockMatrix* assembled() const { return nullptr; }

  /// The part whose range holds `node`.
  static int partOf(const PartBounds& bounds, Eigen::Index node) {
    int p = 0;
    while (node >= bounds[static_cast<std::size_t>(p) + 1]) ++p;
    return p;
  }

  /// Bounds of kParts consecutive node ranges holding about equal shares of a product's work,
  /// from workBefore(j): the work of nodes [0, j) (non-decreasing, 0 at j = 0).
  template <typename WorkBefore>
  static PartBounds balancedPartBounds(Eigen::Index nodeCount, const WorkBefore& workBefore) {
    PartBounds bounds{};
    const Eigen::Index total = workBefore(nodeCount);
    Eigen::Index j = 0;
    for (int p = 1; p < kParts; ++p) {
      while (j < nodeCount && workBefore(j) * kParts < total * p) ++j;
      bounds[static_cast<std::size_t>(p)] = j;
    }
    bounds[kParts] = nodeCount;
    return bounds;
  }

 protected:
  BlockLinearOperator() = default;
  BlockLinearOperator(const BlockLinearOperator&) = default;
  BlockLinearOperator& operator=(const BlockLinearOperator&) = default;
};

}  // namespace tissuesim
