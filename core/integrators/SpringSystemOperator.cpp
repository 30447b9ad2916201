#include "integrators/SpringSystemOperator.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace tissuesim {

SpringSystemOperator::SpringSystemOperator(const SpringMesh& mesh)
    : m_mesh(mesh),
      m_incidentStart(static_cast<std::size_t>(mesh.nodeCount()) + 1, 0),
      m_isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0) {
  const Eigen::Index nodes = mesh.nodeCount();
  const Eigen::Index springs = mesh.springCount();
  if (3 * nodes > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("SpringSystemOperator: " + std::to_string(nodes) +
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
  // Parts of about equal incident springs (each part's work: one entry per spring it touches).
  m_bounds = balancedPartBounds(nodes, [this](Eigen::Index j) {
    return static_cast<Eigen::Index>(m_incidentStart[static_cast<std::size_t>(j)]);
  });
  const auto partOf = [&](int node) {
    int p = 0;
    while (node >= m_bounds[static_cast<std::size_t>(p) + 1]) ++p;
    return p;
  };
  // Each part's three lists, in spring order.
  std::array<std::array<std::vector<SpringEntry>, 3>, kParts> lists;
  for (Eigen::Index s = 0; s < springs; ++s) {
    const int a = mesh.springs(0, s);
    const int b = mesh.springs(1, s);
    const SpringEntry entry{3 * a, 3 * b, static_cast<int>(s)};
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
  m_fixedStart.fill(0);
  m_termDiagonals.resize(nodes, kReservedTerms);
}

void SpringSystemOperator::setSpringBlocks(const AxialBlocks& blocks) {
  if (blocks.cols() != m_mesh.springCount()) {
    throw std::invalid_argument("SpringSystemOperator: " + std::to_string(blocks.cols()) +
                                " blocks for " + std::to_string(m_mesh.springCount()) + " springs");
  }
  m_blocks = &blocks;
}

void SpringSystemOperator::setVolumeBlocks(const VolumeBlocks* blocks) {
  if (blocks != nullptr && blocks->cols() != m_mesh.tets.cols()) {
    throw std::invalid_argument("SpringSystemOperator: " + std::to_string(blocks->cols()) +
                                " volume blocks for " + std::to_string(m_mesh.tets.cols()) +
                                " tets");
  }
  if (blocks != nullptr && m_tetIncidence.start.empty()) buildTetLists();
  m_volumeBlocks = blocks;
}

void SpringSystemOperator::buildTetLists() {
  m_tetIncidence = TetIncidence(m_mesh.tets, m_mesh.nodeCount());
  const auto partOf = [&](int node) {
    int p = 0;
    while (node >= m_bounds[static_cast<std::size_t>(p) + 1]) ++p;
    return p;
  };
  std::array<std::array<std::vector<TetEntry>, 2>, kParts> lists;
  for (Eigen::Index t = 0; t < m_mesh.tets.cols(); ++t) {
    std::array<int, 4> parts{};
    TetEntry entry{};
    entry.tet = static_cast<int>(t);
    for (std::size_t i = 0; i < 4; ++i) {
      entry.rows[i] = 3 * m_mesh.tets(static_cast<Eigen::Index>(i), t);
      parts[i] = partOf(m_mesh.tets(static_cast<Eigen::Index>(i), t));
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
      m_tetListStart[p][list] = m_tetEntries.size();
      m_tetEntries.insert(m_tetEntries.end(), lists[p][list].begin(), lists[p][list].end());
    }
    m_tetListStart[p][2] = m_tetEntries.size();
  }
}

template <bool AllOwn>
void SpringSystemOperator::addTetProducts(std::size_t begin, std::size_t end, const double* x,
                                          double* y) const {
  // c g (g . x) on the tet's own nodes.
  const double* const blocks = m_volumeBlocks->data();
  for (std::size_t k = begin; k < end; ++k) {
    const TetEntry& entry = m_tetEntries[k];
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

void SpringSystemOperator::setFixedDofs(const std::vector<char>& isFixed) {
  if (isFixed.size() != m_isFixed.size()) {
    throw std::invalid_argument("SpringSystemOperator: " + std::to_string(isFixed.size()) +
                                " DOF flags for " + std::to_string(m_isFixed.size()) + " DOFs");
  }
  if (isFixed == m_isFixed) return;
  m_isFixed = isFixed;
  m_fixedDofs.clear();
  for (std::size_t p = 0; p < kParts; ++p) {
    m_fixedStart[p] = m_fixedDofs.size();
    for (Eigen::Index d = 3 * m_bounds[p]; d < 3 * m_bounds[p + 1]; ++d) {
      if (m_isFixed[static_cast<std::size_t>(d)] != 0) m_fixedDofs.push_back(d);
    }
  }
  m_fixedStart[kParts] = m_fixedDofs.size();
}

void SpringSystemOperator::setTerms(const std::vector<RankOneTerm>* terms) {
  m_terms = terms != nullptr && !terms->empty() ? terms : nullptr;
  if (m_terms != nullptr) {
    m_termDiagonals.set(*m_terms);
  } else {
    m_termDiagonals.clear();
  }
}

void SpringSystemOperator::multiplyPart(int part, const double* x, double* y) const {
  const auto p = static_cast<std::size_t>(part);
  const Eigen::Index first = m_bounds[p];
  const Eigen::Index last = m_bounds[p + 1];
  const double* const mass = m_mesh.nodeMass_kg.data();
  for (Eigen::Index j = first; j < last; ++j) {
    const double weight = m_massWeight * mass[j] + m_shift_N_m;  // as Newton adds it to a matrix
    for (Eigen::Index d = 3 * j; d < 3 * j + 3; ++d) y[d] = weight * x[d];
  }
  const std::array<std::size_t, 4>& lists = m_listStart[p];
  addSpringProducts<true, true>(lists[0], lists[1], x, y);
  addSpringProducts<true, false>(lists[1], lists[2], x, y);
  addSpringProducts<false, true>(lists[2], lists[3], x, y);
  if (m_volumeBlocks != nullptr) {
    const std::array<std::size_t, 3>& tetLists = m_tetListStart[p];
    addTetProducts<true>(tetLists[0], tetLists[1], x, y);
    addTetProducts<false>(tetLists[1], tetLists[2], x, y);
  }
  if (m_terms != nullptr) {
    // k u (u . x) on this part's nodes of each term.
    for (const RankOneTerm& term : *m_terms) {
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
  for (std::size_t i = m_fixedStart[p]; i < m_fixedStart[p + 1]; ++i)
    y[m_fixedDofs[i]] = x[m_fixedDofs[i]];
}

template <bool AddA, bool AddB>
void SpringSystemOperator::addSpringProducts(std::size_t begin, std::size_t end, const double* x,
                                             double* y) const {
  // f = K_e (x_b - x_a) = c n (n . d) + l d: +f on b's row, -f on a's. The springs come sorted
  // by their a (buildSpringMesh), so a's row takes a run of consecutive springs: their sum is
  // kept in registers and written once per run, not read back and stored once per spring
  // (a chain through store-to-load forwarding that made the loop half as fast).
  const double* const k = m_blocks->data();
  int runRow = -1;
  double run0 = 0.0, run1 = 0.0, run2 = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    const SpringEntry& entry = m_entries[i];
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

Eigen::Matrix3d SpringSystemOperator::diagonalBlock(Eigen::Index j) const {
  const auto node = static_cast<std::size_t>(j);
  // The upper triangle of sum_e (c n n^T + l I), in scalars: an Eigen 3x3 temporary a spring
  // made this pass several times slower than a product.
  double b00 = 0.0, b01 = 0.0, b02 = 0.0, b11 = 0.0, b12 = 0.0, b22 = 0.0;
  const double* const k = m_blocks->data();
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
  if (m_volumeBlocks != nullptr) {
    for (int e = m_tetIncidence.start[node]; e < m_tetIncidence.start[node + 1]; ++e) {
      const int entry = m_tetIncidence.entries[static_cast<std::size_t>(e)];
      const double* const column =
          m_volumeBlocks->data() + 13 * static_cast<std::ptrdiff_t>(entry >> 2);
      const double* const g = column + 3 * (entry & 3);
      const double c = column[12];
      b00 += c * g[0] * g[0];
      b01 += c * g[0] * g[1];
      b02 += c * g[0] * g[2];
      b11 += c * g[1] * g[1];
      b12 += c * g[1] * g[2];
      b22 += c * g[2] * g[2];
    }
  }
  const double weight = m_massWeight * m_mesh.nodeMass_kg[j] + m_shift_N_m;
  Eigen::Matrix3d block;
  block << b00 + weight, b01, b02, b01, b11 + weight, b12, b02, b12, b22 + weight;
  if (const Eigen::Matrix3d* termDiagonal = m_termDiagonals.at(j)) block += *termDiagonal;
  for (int c = 0; c < 3; ++c) {
    if (m_isFixed[3 * node + static_cast<std::size_t>(c)] == 0) continue;
    block.row(c).setZero();
    block.col(c).setZero();
    block(c, c) = 1.0;
  }
  return block;
}

double SpringSystemOperator::largestDiagonalEntry() const {
  double largest = 0.0;
  for (Eigen::Index j = 0; j < nodeCount(); ++j)
    largest = std::max(largest, diagonalBlock(j).diagonal().maxCoeff());
  return largest;
}

}  // namespace tissuesim
