// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringMesh.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tissuesim {

SpringMesh buildSpringMesh(const TetMesh& mesh, double density_kg_m3) {
  validateTetMesh(mesh, "spring mesh");
  if (!(density_kg_m3 > 0.0)) throw std::invalid_argument("spring mesh: density must be > 0");

  SpringMesh out;
  out.restPositions_m = mesh.nodes_m;
  out.tets = mesh.tets;
  out.tetRestVolume_m3.resize(mesh.tetCount());
  out.nodeMass_kg = Eigen::VectorXd::Zero(mesh.nodeCount());

  // Every tet edge with its volume share, then sorted and merged into unique springs.
  struct EdgeShare {
    int a;
    int b;
    double volume;
  };
  std::vector<EdgeShare> shares;
  shares.reserve(static_cast<std::size_t>(6 * mesh.tetCount()));
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    const double volume = signedTetVolume(mesh.nodes_m, mesh.tets, t);
    if (!(volume > 0.0)) {
      throw std::invalid_argument("spring mesh: tet " + std::to_string(t) +
                                  (volume < 0.0 ? " is inverted" : " has zero volume") +
                                  " (volume " + std::to_string(volume) + " m^3)");
    }
    out.tetRestVolume_m3[t] = volume;
    for (int i = 0; i < 4; ++i) {
      out.nodeMass_kg[mesh.tets(i, t)] += density_kg_m3 * volume / 4.0;
      for (int j = i + 1; j < 4; ++j) {
        const int a = std::min(mesh.tets(i, t), mesh.tets(j, t));
        const int b = std::max(mesh.tets(i, t), mesh.tets(j, t));
        shares.push_back({a, b, volume / 6.0});
      }
    }
  }
  std::sort(shares.begin(), shares.end(), [](const EdgeShare& x, const EdgeShare& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  std::vector<EdgeShare> unique;
  for (const EdgeShare& share : shares) {
    if (!unique.empty() && unique.back().a == share.a && unique.back().b == share.b) {
      unique.back().volume += share.volume;
    } else {
      unique.push_back(share);
    }
  }
  const auto count = static_cast<Eigen::Index>(unique.size());
  out.springs.resize(2, count);
  out.restLength_m.resize(count);
  out.volume_m3.resize(count);
  for (Eigen::Index s = 0; s < count; ++s) {
    const EdgeShare& edge = unique[static_cast<std::size_t>(s)];
    out.springs.col(s) << edge.a, edge.b;
    out.restLength_m[s] = (mesh.nodes_m.col(edge.b) - mesh.nodes_m.col(edge.a)).norm();
    out.volume_m3[s] = edge.volume;
  }
  return out;
}

}  // namespace tissuesim
