// SPDX-License-Identifier: Apache-2.0
#pragma once
// A term k u u^T of a node-block matrix whose vector u has at most kMaxTermNodes nonzero 3-blocks:
// an instrument contact's stiffness k w_i w_j n n^T on the nodes that carry the contact point
// (PenaltyContacts: a tet's four nodes for a point on the drawn surface, a boundary triangle's
// three for one on the tet mesh's own surface), u = (w_0 n, ..., w_3 n). BlockConjugateGradient
// can be told of such terms so that its preconditioner carries them exactly.

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace tissuesim {

class NodeBlockMatrix;

/// The most nodes one contact point is carried by: a tet's four.
inline constexpr std::size_t kMaxTermNodes = 4;

struct RankOneTerm {
  std::array<int, kMaxTermNodes> nodes{};
  /// u's 3-blocks at the nodes (dimensionless); a zero block stands for a node u leaves out
  /// (its index may then repeat another's).
  std::array<Eigen::Vector3d, kMaxTermNodes> blocks{
      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
      Eigen::Vector3d::Zero()};
  double stiffness_N_m = 0.0;  ///< k > 0
};

/// The term of a point s = sum_i w_i x_i held along unit `direction` with stiffness k: u's block
/// at node i is w_i direction, zeroed on the DOFs flagged in `fixedDofs` (3#V; null: none fixed),
/// as the solvers zero the matrix's rows there.
RankOneTerm pointTerm(const std::array<int, kMaxTermNodes>& nodes, const Eigen::Vector4d& weights,
                      const Eigen::Vector3d& direction, double stiffness_N_m,
                      const std::vector<char>* fixedDofs);

/// y += sum over the terms of k u (u . x), on the rows of nodes first <= j < last only (x, y:
/// 3#V): one part of a threaded product, each part writing its own rows.
void addRankOneProducts(std::span<const RankOneTerm> terms, Eigen::Index first, Eigen::Index last,
                        const double* x, double* y);
/// matrix += sum over the terms of k u u^T (their nodes must be in the matrix's pattern).
void addRankOneTerms(std::span<const RankOneTerm> terms, NodeBlockMatrix& matrix);

}  // namespace tissuesim
