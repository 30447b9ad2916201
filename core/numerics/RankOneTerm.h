#pragma once
// A term k u u^T of a node-block matrix whose vector u has at most three nonzero 3-blocks:
// an instrument contact's stiffness k w_i w_j n n^T on a triangle's corners (PenaltyContacts),
// u = (w_0 n, w_1 n, w_2 n). BlockConjugateGradient can be told of such terms so that its
// preconditioner carries them exactly.

#include <array>

#include <Eigen/Core>

namespace tissuesim {

struct RankOneTerm {
  std::array<int, 3> nodes{};
  /// u's 3-blocks at the nodes (dimensionless); a zero block stands for a node u leaves out.
  std::array<Eigen::Vector3d, 3> blocks{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                        Eigen::Vector3d::Zero()};
  double stiffness_N_m = 0.0;  ///< k > 0
};

}  // namespace tissuesim
