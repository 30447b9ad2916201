// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringStiffnessProduct.h"

#include <limits>
#include <stdexcept>
#include <string>

#include "numerics/SymmetricBlock.h"

namespace tissuesim {

void SpringStiffnessProduct::addWork(const SpringMesh& mesh, std::vector<Eigen::Index>& nodeWork) {
  for (Eigen::Index s = 0; s < mesh.springCount(); ++s) {
    for (int end = 0; end < 2; ++end) ++nodeWork[static_cast<std::size_t>(mesh.springs(end, s))];
  }
}

SpringStiffnessProduct::SpringStiffnessProduct(const SpringMesh& mesh, const PartBounds& bounds)
    : m_bounds(bounds), m_incidentStart(static_cast<std::size_t>(mesh.nodeCount()) + 1, 0) {
  const Eigen::Index nodes = mesh.nodeCount();
  const Eigen::Index springs = mesh.springCount();
  if (3 * nodes > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("SpringStiffnessProduct: " + std::to_string(nodes) +
                                " nodes (rows must fit an int)");
  }
  // Incidence, each node's springs in spring order.
  for (Eigen::Index s = 0; s < springs; ++s) {
    for (int end = 0; end < 2; ++end)
      ++m_incidentStart[static_cast<std::size_t>(mesh.springs(end, s)) + 1];
  }
  for (std::size_t j = 0; j < static_cast<std::size_t>(nodes); ++j)
    m_incidentStart[j + 1] += m_incidentStart[j];
  m_incident.resize(static_cast<std::size_t>(m_incidentStart.back()));
  std::vector<int> fill(m_incidentStart.begin(), m_incidentStart.end() - 1);
  for (Eigen::Index s = 0; s < springs; ++s) {
    for (int end = 0; end < 2; ++end) {
      m_incident[static_cast<std::size_t>(fill[static_cast<std::size_t>(mesh.springs(end, s))]++)] =
          static_cast<int>(s);
    }
  }
  const auto partOf = [&](int node) { return BlockLinearOperator::partOf(m_bounds, node); };
  // Each part's three lists, in spring order.
  std::array<std::array<std::vector<Entry>, 3>, kParts> lists;
  for (Eigen::Index s = 0; s < springs; ++s) {
    const int a = mesh.springs(0, s);
    const int b = mesh.springs(1, s);
    const Entry entry{3 * a, 3 * b, static_cast<int>(s)};
    const auto pa = static_cast<std::size_t>(partOf(a));
    const auto pb = static_cast<std::size_t>(partOf(b));
    if (pa == pb) {
      lists[pa][0].push_back(entry);
    } else {
      lists[pa][1].push_back(entry);
      lists[pb][2].push_back(entry);
    }
  }
  for (std::size_t p = 0; p < kParts; ++p) {
    for (std::size_t list = 0; list < 3; ++list) {
      m_listStart[p][list] = m_entries.size();
      m_entries.insert(m_entries.end(), lists[p][list].begin(), lists[p][list].end());
    }
    m_listStart[p][3] = m_entries.size();
  }
}

void SpringStiffnessProduct::addPart(int part, const AxialBlocks& blocks, const double* x,
                                     double* y) const {
  const std::array<std::size_t, 4>& lists = m_listStart[static_cast<std::size_t>(part)];
  const double* const k = blocks.data();
  addRange<true, true>(lists[0], lists[1], k, x, y);
  addRange<true, false>(lists[1], lists[2], k, x, y);
  addRange<false, true>(lists[2], lists[3], k, x, y);
}

template <bool AddA, bool AddB>
void SpringStiffnessProduct::addRange(std::size_t begin, std::size_t end, const double* k,
                                      const double* x, double* y) const {
  // f = K_e (x_b - x_a) = c n (n . d) + l d: +f on b's row, -f on a's. The springs come sorted
  // by their a (buildSpringMesh), so a's row takes a run of consecutive springs: their sum is
  // kept in registers and written once per run, not read back and stored once per spring
  // (a chain through store-to-load forwarding that made the loop half as fast).
  int runRow = -1;
  double run0 = 0.0, run1 = 0.0, run2 = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    const Entry& entry = m_entries[i];
    const double* const ks = k + 5 * static_cast<std::ptrdiff_t>(entry.spring);
    const double* const xa = x + entry.rowA;
    const double* const xb = x + entry.rowB;
    const double d0 = xb[0] - xa[0];
    const double d1 = xb[1] - xa[1];
    const double d2 = xb[2] - xa[2];
    const double t = ks[3] * (ks[0] * d0 + ks[1] * d1 + ks[2] * d2);
    const double f0 = t * ks[0] + ks[4] * d0;
    const double f1 = t * ks[1] + ks[4] * d1;
    const double f2 = t * ks[2] + ks[4] * d2;
    if constexpr (AddA) {
      if (entry.rowA != runRow) {
        if (runRow >= 0) {
          y[runRow] -= run0;
          y[runRow + 1] -= run1;
          y[runRow + 2] -= run2;
        }
        runRow = entry.rowA;
        run0 = run1 = run2 = 0.0;
      }
      run0 += f0;
      run1 += f1;
      run2 += f2;
    }
    if constexpr (AddB) {
      double* const yb = y + entry.rowB;
      yb[0] += f0;
      yb[1] += f1;
      yb[2] += f2;
    }
  }
  if constexpr (AddA) {
    if (runRow >= 0) {
      y[runRow] -= run0;
      y[runRow + 1] -= run1;
      y[runRow + 2] -= run2;
    }
  }
}

void SpringStiffnessProduct::addDiagonalBlock(Eigen::Index j, const AxialBlocks& blocks,
                                              Eigen::Matrix3d& block) const {
  const auto node = static_cast<std::size_t>(j);
  // The upper triangle of sum_e (c n n^T + l I), in scalars: an Eigen 3x3 temporary a spring
  // made this pass several times slower than a product.
  double b00 = 0.0, b01 = 0.0, b02 = 0.0, b11 = 0.0, b12 = 0.0, b22 = 0.0;
  const double* const k = blocks.data();
  for (int i = m_incidentStart[node]; i < m_incidentStart[node + 1]; ++i) {
    const double* const ks =
        k + 5 * static_cast<std::ptrdiff_t>(m_incident[static_cast<std::size_t>(i)]);
    const double c0 = ks[3] * ks[0];
    const double c1 = ks[3] * ks[1];
    const double c2 = ks[3] * ks[2];
    b00 += c0 * ks[0] + ks[4];
    b01 += c0 * ks[1];
    b02 += c0 * ks[2];
    b11 += c1 * ks[1] + ks[4];
    b12 += c1 * ks[2];
    b22 += c2 * ks[2] + ks[4];
  }
  addSymmetric(block, b00, b01, b02, b11, b12, b22);
}

}  // namespace tissuesim
