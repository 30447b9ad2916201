// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeStiffnessProduct.h"

namespace tissuesim {

CellIncidence::CellIncidence(const VolumeCells& cells, Eigen::Index nodeCount)
    : start(static_cast<std::size_t>(nodeCount) + 1, 0) {
  const auto cellNodes = [&](Eigen::Index c) {
    return cells.nodeCount[static_cast<std::size_t>(c)];
  };
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    for (int i = 0; i < cellNodes(c); ++i) ++start[static_cast<std::size_t>(cells.nodes(i, c)) + 1];
  }
  for (std::size_t j = 0; j < static_cast<std::size_t>(nodeCount); ++j) start[j + 1] += start[j];
  entries.resize(static_cast<std::size_t>(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    for (int i = 0; i < cellNodes(c); ++i) {
      entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(cells.nodes(i, c))]++)] =
          static_cast<int>(VolumeCells::kMaxNodes * c + i);
    }
  }
}

VolumeStiffnessProduct::VolumeStiffnessProduct(const VolumeCells& cells, const PartBounds& bounds)
    : m_bounds(bounds) {
  const auto partOf = [&](int node) { return BlockLinearOperator::partOf(m_bounds, node); };
  std::array<std::array<std::vector<Entry>, 2>, kParts> lists;
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    std::array<int, VolumeCells::kMaxNodes> parts{};
    Entry entry{};
    entry.cell = static_cast<int>(c);
    entry.nodeCount = cells.nodeCount[static_cast<std::size_t>(c)];
    for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
      entry.rows[i] = 3 * cells.nodes(static_cast<Eigen::Index>(i), c);
      parts[i] = partOf(cells.nodes(static_cast<Eigen::Index>(i), c));
    }
    const unsigned all = (1u << entry.nodeCount) - 1u;
    for (int p = 0; p < kParts; ++p) {
      entry.ownNodes = 0;
      for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
        if (parts[i] == p) entry.ownNodes |= 1u << i;
      }
      if (entry.ownNodes == 0) continue;
      lists[static_cast<std::size_t>(p)][entry.ownNodes == all ? 0 : 1].push_back(entry);
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

void VolumeStiffnessProduct::addPart(int part, const VolumeBlocks& blocks, const double* x,
                                     double* y) const {
  const std::array<std::size_t, 3>& lists = m_listStart[static_cast<std::size_t>(part)];
  addRange<true>(lists[0], lists[1], blocks.data(), x, y);
  addRange<false>(lists[1], lists[2], blocks.data(), x, y);
}

template <bool AllOwn>
void VolumeStiffnessProduct::addRange(std::size_t begin, std::size_t end, const double* blocks,
                                      const double* x, double* y) const {
  // k g (g . x) on the cell's own nodes.
  for (std::size_t k = begin; k < end; ++k) {
    const Entry& entry = m_entries[k];
    const double* const g = blocks + kVolumeBlockRows * static_cast<std::ptrdiff_t>(entry.cell);
    const auto count = static_cast<std::size_t>(entry.nodeCount);
    double gx = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      const double* const xi = x + entry.rows[i];
      gx += g[3 * i] * xi[0] + g[3 * i + 1] * xi[1] + g[3 * i + 2] * xi[2];
    }
    const double scale = g[kVolumeBlockRows - 1] * gx;
    for (std::size_t i = 0; i < count; ++i) {
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
