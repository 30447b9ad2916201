// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeStiffnessProduct.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "numerics/CpuFeatures.h"

namespace tissuesim {

#if defined(__x86_64__)
namespace {

/// A node's three values in one register, the fourth lane zero, from a pair and a single load:
/// nothing past them is read (they may end x).
__attribute__((target("avx"))) inline __m256d loadNode(const double* v) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v)), _mm_load_sd(v + 2), 1);
}

/// VolumeStiffnessProduct::addRange's loop with AVX and FMA, a node's three values in one
/// register, over the entries [first, last).
template <bool AllOwn, typename Entry>
__attribute__((target("avx,fma"))) void addEntriesAvxFma(const Entry* first, const Entry* last,
                                                         const double* blocks, const double* x,
                                                         double* y) {
  for (const Entry* e = first; e != last; ++e) {
    const Entry& entry = *e;
    const double* const g = blocks + kVolumeBlockRows * static_cast<std::ptrdiff_t>(entry.cell);
    const auto count = static_cast<std::size_t>(entry.nodeCount);
    __m256d sum = _mm256_setzero_pd();
    // g's four values from slot i (the fourth the next slot's, or k) meet x's zero lane.
    for (std::size_t i = 0; i < count; ++i)
      sum = _mm256_fmadd_pd(_mm256_loadu_pd(g + 3 * i), loadNode(x + entry.rows[i]), sum);
    const __m128d pair = _mm_add_pd(_mm256_castpd256_pd128(sum), _mm256_extractf128_pd(sum, 1));
    const double gx = _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)));
    const __m256d scale = _mm256_set1_pd(g[kVolumeBlockRows - 1] * gx);
    const auto own = static_cast<std::size_t>(entry.ownCount);
    for (std::size_t o = 0; o < own; ++o) {
      const std::size_t i = AllOwn ? o : entry.ownSlots[o];
      // Three values written back, not four: the fourth is another node's, maybe another part's.
      double* const yi = y + entry.rows[i];
      const __m256d add = _mm256_mul_pd(scale, _mm256_loadu_pd(g + 3 * i));
      _mm_storeu_pd(yi, _mm_add_pd(_mm_loadu_pd(yi), _mm256_castpd256_pd128(add)));
      yi[2] += _mm_cvtsd_f64(_mm256_extractf128_pd(add, 1));
    }
  }
}

}  // namespace
#endif

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

VolumeStiffnessProduct::VolumeStiffnessProduct(const VolumeCells& cells, const PartBounds& bounds,
                                               Kernel kernel)
    : m_bounds(bounds), m_isAvxFma(kernel == Kernel::Fastest && hasAvxAndFma()) {
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
    for (int p = 0; p < kParts; ++p) {
      entry.ownCount = 0;
      entry.ownSlots.fill(0);
      for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
        if (parts[i] == p)
          entry.ownSlots[static_cast<std::size_t>(entry.ownCount++)] = static_cast<std::uint8_t>(i);
      }
      if (entry.ownCount == 0) continue;
      lists[static_cast<std::size_t>(p)][entry.ownCount == entry.nodeCount ? 0 : 1].push_back(
          entry);
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
#if defined(__x86_64__)
  if (m_isAvxFma) {
    const Entry* const entries = m_entries.data();
    addEntriesAvxFma<true>(entries + lists[0], entries + lists[1], blocks.data(), x, y);
    addEntriesAvxFma<false>(entries + lists[1], entries + lists[2], blocks.data(), x, y);
    return;
  }
#endif
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
    const auto own = static_cast<std::size_t>(entry.ownCount);
    for (std::size_t o = 0; o < own; ++o) {
      const std::size_t i = AllOwn ? o : entry.ownSlots[o];
      double* const yi = y + entry.rows[i];
      yi[0] += scale * g[3 * i];
      yi[1] += scale * g[3 * i + 1];
      yi[2] += scale * g[3 * i + 2];
    }
  }
}

}  // namespace tissuesim
