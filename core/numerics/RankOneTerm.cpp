// SPDX-License-Identifier: Apache-2.0
#include "numerics/RankOneTerm.h"

#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

RankOneTerm pointTerm(const std::array<int, kMaxTermNodes>& nodes, const Eigen::Vector4d& weights,
                      const Eigen::Vector3d& direction, double stiffness_N_m,
                      const std::vector<char>* fixedDofs) {
  RankOneTerm term;
  term.nodes = nodes;
  term.stiffness_N_m = stiffness_N_m;
  for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
    const double w = weights[static_cast<Eigen::Index>(i)];
    if (w == 0.0) continue;
    for (int axis = 0; axis < 3; ++axis) {
      const bool isFree =
          fixedDofs == nullptr || (*fixedDofs)[static_cast<std::size_t>(3 * nodes[i] + axis)] == 0;
      term.blocks[i][axis] = isFree ? w * direction[axis] : 0.0;
    }
  }
  return term;
}

void addRankOneProducts(std::span<const RankOneTerm> terms, Eigen::Index first, Eigen::Index last,
                        const double* x, double* y) {
  for (const RankOneTerm& term : terms) {
    double ux = 0.0;
    bool touchesPart = false;
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      ux += term.blocks[i].dot(Eigen::Map<const Eigen::Vector3d>(x + 3 * term.nodes[i]));
      touchesPart = touchesPart || (term.nodes[i] >= first && term.nodes[i] < last);
    }
    if (!touchesPart) continue;
    const double scale = term.stiffness_N_m * ux;
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      if (term.nodes[i] < first || term.nodes[i] >= last) continue;
      Eigen::Map<Eigen::Vector3d>(y + 3 * term.nodes[i]) += scale * term.blocks[i];
    }
  }
}

void addRankOneTerms(std::span<const RankOneTerm> terms, NodeBlockMatrix& matrix) {
  for (const RankOneTerm& term : terms) {
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      if (term.blocks[i].isZero(0.0)) continue;
      for (std::size_t j = 0; j < kMaxTermNodes; ++j) {
        if (term.blocks[j].isZero(0.0)) continue;
        matrix.addBlock(term.nodes[i], term.nodes[j],
                        term.stiffness_N_m * term.blocks[i] * term.blocks[j].transpose());
      }
    }
  }
}

}  // namespace tissuesim
