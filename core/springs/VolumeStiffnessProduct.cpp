// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeStiffnessProduct.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "numerics/AvxLanes.h"
#include "numerics/CpuFeatures.h"

namespace tissuesim {

#if defined(__x86_64__)
namespace {

/// A node's three values in one register, the fourth lane zero, from a pair and a single load:
/// nothing past them is read (they may end x).
__attribute__((target("avx"))) inline __m256d loadNode(const double* v) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v)), _mm_load_sd(v + 2), 1);
}

/// VolumeStiffnessProduct's two loops with AVX and FMA, a node's three values in one register.
/// scales[k] = k_c (g_c . x) for the entries [first, last) (scales: the first's).
template <typename Entry>
__attribute__((target("avx,fma"))) void scaleEntriesAvxFma(const Entry* first, const Entry* last,
                                                           const double* blocks, const double* x,
                                                           double* scales) {
  for (const Entry* e = first; e != last; ++e, ++scales) {
    const double* const g = blocks + kVolumeBlockRows * static_cast<std::ptrdiff_t>(e->cell);
    const auto count = static_cast<std::size_t>(e->nodeCount);
    // g's four values from slot i (the fourth the next slot's, or k) meet x's zero lane.
    __m256d sum = _mm256_setzero_pd();
    for (std::size_t i = 0; i < count; ++i)
      sum = _mm256_fmadd_pd(_mm256_loadu_pd(g + 3 * i), loadNode(x + e->rows[i]), sum);
    *scales = g[kVolumeBlockRows - 1] * sumOfLanes(sum);
  }
}

/// y_j += sum over j's terms of scale g_c,slot for the nodes [begin, end).
template <typename Term>
__attribute__((target("avx,fma"))) void gatherNodesAvxFma(Eigen::Index begin, Eigen::Index end,
                                                          const int* start, const Term* terms,
                                                          const double* blocks,
                                                          const double* scales, double* y) {
  for (Eigen::Index j = begin; j < end; ++j) {
    // Four lanes summed, the fourth (the next slot's g, or k) never written.
    __m256d sum = _mm256_setzero_pd();
    for (int t = start[j]; t < start[j + 1]; ++t) {
      sum = _mm256_fmadd_pd(_mm256_broadcast_sd(scales + terms[t].entry),
                            _mm256_loadu_pd(blocks + terms[t].offset), sum);
    }
    double* const yj = y + 3 * j;
    _mm_storeu_pd(yj, _mm_add_pd(_mm_loadu_pd(yj), _mm256_castpd256_pd128(sum)));
    yj[2] += _mm_cvtsd_f64(_mm256_extractf128_pd(sum, 1));
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
  // Each part's entries: every cell with a node among its own, in cell order.
  for (std::size_t p = 0; p < kParts; ++p) {
    m_partStart[p] = m_entries.size();
    for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
      Entry entry{};
      entry.cell = static_cast<int>(c);
      entry.nodeCount = cells.nodeCount[static_cast<std::size_t>(c)];
      bool isListed = false;
      for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
        const int node = cells.nodes(static_cast<Eigen::Index>(i), c);
        entry.rows[i] = 3 * node;
        isListed = isListed || partOf(node) == static_cast<int>(p);
      }
      if (isListed) m_entries.push_back(entry);
    }
  }
  m_partStart[kParts] = m_entries.size();
  m_scales.assign(m_entries.size(), 0.0);
  // Each node's terms, from its own part's entries, in entry order.
  const Eigen::Index nodeCount = m_bounds[kParts];
  std::vector<std::vector<Term>> nodeTerms(static_cast<std::size_t>(nodeCount));
  for (std::size_t p = 0; p < kParts; ++p) {
    for (std::size_t k = m_partStart[p]; k < m_partStart[p + 1]; ++k) {
      const Entry& entry = m_entries[k];
      for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
        const int node = entry.rows[i] / 3;
        if (partOf(node) != static_cast<int>(p)) continue;
        nodeTerms[static_cast<std::size_t>(node)].push_back(
            {static_cast<int>(k), kVolumeBlockRows * entry.cell + 3 * static_cast<int>(i)});
      }
    }
  }
  m_termStart.assign(1, 0);
  for (const std::vector<Term>& terms : nodeTerms) {
    m_terms.insert(m_terms.end(), terms.begin(), terms.end());
    m_termStart.push_back(static_cast<int>(m_terms.size()));
  }
}

void VolumeStiffnessProduct::addPart(int part, const VolumeBlocks& blocks, const double* x,
                                     double* y) const {
  // First k_c (g_c . x) for every cell with a node in the part (a cell across two parts is
  // taken by both: no part reads another's), then each node gathers its cells' k g (g . x).
  const auto p = static_cast<std::size_t>(part);
  const Eigen::Index begin = m_bounds[p];
  const Eigen::Index end = m_bounds[p + 1];
  double* const scales = m_scales.data();
#if defined(__x86_64__)
  if (m_isAvxFma) {
    const Entry* const entries = m_entries.data();
    scaleEntriesAvxFma(entries + m_partStart[p], entries + m_partStart[p + 1], blocks.data(), x,
                       scales + m_partStart[p]);
    gatherNodesAvxFma(begin, end, m_termStart.data(), m_terms.data(), blocks.data(), scales, y);
    return;
  }
#endif
  for (std::size_t k = m_partStart[p]; k < m_partStart[p + 1]; ++k) {
    const Entry& entry = m_entries[k];
    const double* const g =
        blocks.data() + kVolumeBlockRows * static_cast<std::ptrdiff_t>(entry.cell);
    double gx = 0.0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(entry.nodeCount); ++i) {
      const double* const xi = x + entry.rows[i];
      gx += g[3 * i] * xi[0] + g[3 * i + 1] * xi[1] + g[3 * i + 2] * xi[2];
    }
    scales[k] = g[kVolumeBlockRows - 1] * gx;
  }
  for (Eigen::Index j = begin; j < end; ++j) {
    double y0 = 0.0, y1 = 0.0, y2 = 0.0;
    for (int t = m_termStart[static_cast<std::size_t>(j)];
         t < m_termStart[static_cast<std::size_t>(j) + 1]; ++t) {
      const Term& term = m_terms[static_cast<std::size_t>(t)];
      const double* const g = blocks.data() + term.offset;
      const double scale = scales[term.entry];
      y0 += scale * g[0];
      y1 += scale * g[1];
      y2 += scale * g[2];
    }
    y[3 * j] += y0;
    y[3 * j + 1] += y1;
    y[3 * j + 2] += y2;
  }
}

}  // namespace tissuesim
