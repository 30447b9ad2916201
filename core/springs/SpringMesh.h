// SPDX-License-Identifier: Apache-2.0
#pragma once
// The spring network built from a tetrahedral mesh: one spring per unique tet edge.
//
// Data are structures of arrays, contiguous per spring (SI units):
//   springs          2 by #S  node indices (a, b), a < b
//   restLength_m     #S       |X_b - X_a| at rest
//   volume_m3        #S       V_e, the spring's share of the tet volume around it
//   nodeMass_kg      #V       lumped masses
//
// Volume share (our rule): each tet gives one sixth of its rest volume to each of its six
// edges, so V_e = sum over tets t containing e of V_t / 6 and sum_e V_e = the mesh volume.
// The spring then carries energy V_e W_T(lambda) (docs/model.md), which makes the
// network's energy density W_T when all springs share one stretch.
// Masses: each tet gives rho V_t / 4 to each of its nodes (lumped mass matrix).

#include <Eigen/Core>

#include "mesh/TetMesh.h"

namespace tissuesim {

struct SpringMesh {
  Eigen::Matrix3Xd restPositions_m;  ///< 3 by #V
  Eigen::Matrix2Xi springs;          ///< 2 by #S
  Eigen::VectorXd restLength_m;      ///< #S
  Eigen::VectorXd volume_m3;         ///< #S
  Eigen::VectorXd nodeMass_kg;       ///< #V
  Eigen::Matrix4Xi tets;             ///< 4 by #T, kept for the optional volume term
  Eigen::VectorXd tetRestVolume_m3;  ///< #T

  Eigen::Index nodeCount() const { return restPositions_m.cols(); }
  Eigen::Index springCount() const { return springs.cols(); }
};

/// Builds the network. @param density_kg_m3 > 0.
/// @throws std::invalid_argument for a mesh with bad indices, non-finite nodes, no tets, or an
/// inverted or zero-volume tet (re-orient or remove it first; see inspectTets).
SpringMesh buildSpringMesh(const TetMesh& mesh, double density_kg_m3);

}  // namespace tissuesim
