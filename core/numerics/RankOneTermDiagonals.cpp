// SPDX-License-Identifier: Apache-2.0
#include "numerics/RankOneTermDiagonals.h"

namespace tissuesim {

void RankOneTermDiagonals::resize(Eigen::Index nodeCount, std::size_t reservedTerms) {
  m_slot.assign(static_cast<std::size_t>(nodeCount), -1);
  m_nodes.clear();
  m_sums.clear();
  m_nodes.reserve(kMaxTermNodes * reservedTerms);
  m_sums.reserve(kMaxTermNodes * reservedTerms);
}

void RankOneTermDiagonals::set(std::span<const RankOneTerm> terms) {
  clear();
  for (const RankOneTerm& term : terms) {
    for (std::size_t i = 0; i < kMaxTermNodes; ++i) {
      const Eigen::Vector3d& u = term.blocks[i];
      if (u.isZero(0.0)) continue;
      int& slot = m_slot[static_cast<std::size_t>(term.nodes[i])];
      if (slot < 0) {
        slot = static_cast<int>(m_nodes.size());
        m_nodes.push_back(term.nodes[i]);
        m_sums.push_back(Eigen::Matrix3d::Zero());
      }
      m_sums[static_cast<std::size_t>(slot)] += term.stiffness_N_m * u * u.transpose();
    }
  }
}

void RankOneTermDiagonals::clear() {
  for (const int node : m_nodes) m_slot[static_cast<std::size_t>(node)] = -1;
  m_nodes.clear();
  m_sums.clear();
}

}  // namespace tissuesim
