#include "springs/TetStiffnessProduct.h"

namespace tissuesim {

TetIncidence::TetIncidence(const Eigen::Matrix4Xi& tets, Eigen::Index nodeCount)
    : start(static_cast<std::size_t>(nodeCount) + 1, 0) {
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int i = 0; i < 4; ++i) ++start[static_cast<std::size_t>(tets(i, t)) + 1];
  }
  for (std::size_t j = 0; j < static_cast<std::size_t>(nodeCount); ++j) start[j + 1] += start[j];
  entries.resize(static_cast<std::size_t>(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    for (int i = 0; i < 4; ++i) {
      entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(tets(i, t))]++)] =
          static_cast<int>(4 * t + i);
    }
  }
}

TetStiffnessProduct::TetStiffnessProduct(const Eigen::Matrix4Xi& tets, const PartBounds& bounds)
    : m_bounds(bounds) {
  const auto partOf = [&](int node) { return BlockLinearOperator::partOf(m_bounds, node); };
  std::array<std::array<std::vector<Entry>, 2>, kParts> lists;
  for (Eigen::Index t = 0; t < tets.cols(); ++t) {
    std::array<int, 4> parts{};
    Entry entry{};
    entry.tet = static_cast<int>(t);
    for (std::size_t i = 0; i < 4; ++i) {
      entry.rows[i] = 3 * tets(static_cast<Eigen::Index>(i), t);
      parts[i] = partOf(tets(static_cast<Eigen::Index>(i), t));
    }
    for (int p = 0; p < kParts; ++p) {
      entry.ownNodes = 0;
      for (std::size_t i = 0; i < 4; ++i) {
        if (parts[i] == p) entry.ownNodes |= 1u << i;
      }
      if (entry.ownNodes == 0) continue;
      lists[static_cast<std::size_t>(p)][entry.ownNodes == 15u ? 0 : 1].push_back(entry);
    }
  }
  for (std::size_t p = 0; p < kParts; ++p) {
    for (std::size_t list = 0; list < 2; ++list) {
      m_listStart[p][list] = m_entries.size();
      m_entries.insert(m_entries.end(), lists[p][list].begin(), lists[p][list].end());
    }
    m_listStart[p][2] = m_entries.size();
  }
}

void TetStiffnessProduct::addPart(int part, const VolumeBlocks& blocks, const double* x,
                                  double* y) const {
  const std::array<std::size_t, 3>& lists = m_listStart[static_cast<std::size_t>(part)];
  addRange<true>(lists[0], lists[1], blocks.data(), x, y);
  addRange<false>(lists[1], lists[2], blocks.data(), x, y);
}

template <bool AllOwn>
void TetStiffnessProduct::addRange(std::size_t begin, std::size_t end, const double* blocks,
                                   const double* x, double* y) const {
  // c g (g . x) on the tet's own nodes.
  for (std::size_t k = begin; k < end; ++k) {
    const Entry& entry = m_entries[k];
    const double* const g = blocks + 13 * static_cast<std::ptrdiff_t>(entry.tet);
    double gx = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      const double* const xi = x + entry.rows[i];
      gx += g[3 * i] * xi[0] + g[3 * i + 1] * xi[1] + g[3 * i + 2] * xi[2];
    }
    const double scale = g[12] * gx;
    for (std::size_t i = 0; i < 4; ++i) {
      if constexpr (!AllOwn) {
        if ((entry.ownNodes & (1u << i)) == 0) continue;
      }
      double* const yi = y + entry.rows[i];
      yi[0] += scale * g[3 * i];
      yi[1] += scale * g[3 * i + 1];
      yi[2] += scale * g[3 * i + 2];
    }
  }
}

}  // namespace tissuesim
