// SPDX-License-Identifier: Apache-2.0
#include "fem/NodeRowStiffness.h"

#include <algorithm>
#include <utility>

#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

NodeRowStiffness::NodeRowStiffness(NodeStars neighbours) : m_neighbours(std::move(neighbours)) {
  const auto entries = static_cast<Eigen::Index>(m_neighbours.nodes.size());
  for (Blocks& slot : m_slots) slot.setZero(9, entries);
}

void NodeRowStiffness::clearRow(Blocks& blocks, Eigen::Index j) const {
  const auto u = static_cast<std::size_t>(j);
  blocks.middleCols(m_neighbours.start[u], m_neighbours.start[u + 1] - m_neighbours.start[u])
      .setZero();
}

void NodeRowStiffness::addProductWork(std::vector<Eigen::Index>& nodeWork) const {
  for (std::size_t j = 0; j + 1 < m_neighbours.start.size(); ++j) {
    nodeWork[j] += 9 * (m_neighbours.start[j + 1] - m_neighbours.start[j]);
  }
}

void NodeRowStiffness::addProduct(Eigen::Index first, Eigen::Index last, const double* x,
                                  double* y) const {
  const Blocks& blocks = current();
  for (Eigen::Index j = first; j < last; ++j) {
    const auto u = static_cast<std::size_t>(j);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int e = m_neighbours.start[u]; e < m_neighbours.start[u + 1]; ++e) {
      sum += Eigen::Map<const Eigen::Matrix3d>(blocks.col(e).data()) *
             Eigen::Map<const Eigen::Vector3d>(x +
                                               3 * m_neighbours.nodes[static_cast<std::size_t>(e)]);
    }
    Eigen::Map<Eigen::Vector3d>(y + 3 * j) += sum;
  }
}

void NodeRowStiffness::addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
  block += Eigen::Map<const Eigen::Matrix3d>(
      current().col(entry(static_cast<int>(j), static_cast<int>(j))).data());
}

void NodeRowStiffness::addStiffness(NodeBlockMatrix& matrix) const {
  const Blocks& blocks = current();
  for (std::size_t j = 0; j + 1 < m_neighbours.start.size(); ++j) {
    for (int e = m_neighbours.start[j]; e < m_neighbours.start[j + 1]; ++e) {
      matrix.addBlock(static_cast<int>(j), m_neighbours.nodes[static_cast<std::size_t>(e)],
                      Eigen::Map<const Eigen::Matrix3d>(blocks.col(e).data()));
    }
  }
}

NodeStars cellNeighbours(const std::vector<int>& start, const std::vector<int>& nodes,
                         Eigen::Index nodeCount) {
  const auto count = static_cast<std::size_t>(nodeCount);
  // Each node's cells, then the union of their nodes.
  std::vector<int> cellStart(count + 1, 0);
  for (const int node : nodes) ++cellStart[static_cast<std::size_t>(node) + 1];
  for (std::size_t j = 0; j < count; ++j) cellStart[j + 1] += cellStart[j];
  std::vector<int> cellsOfNode(nodes.size());
  std::vector<int> fill(cellStart.begin(), cellStart.end() - 1);
  for (std::size_t c = 0; c + 1 < start.size(); ++c) {
    for (int e = start[c]; e < start[c + 1]; ++e) {
      cellsOfNode[static_cast<std::size_t>(
          fill[static_cast<std::size_t>(nodes[static_cast<std::size_t>(e)])]++)] =
          static_cast<int>(c);
    }
  }
  NodeStars rows;
  rows.start.assign(count + 1, 0);
  std::vector<int> row;
  for (std::size_t j = 0; j < count; ++j) {
    row.assign(1, static_cast<int>(j));
    for (int k = cellStart[j]; k < cellStart[j + 1]; ++k) {
      const auto c = static_cast<std::size_t>(cellsOfNode[static_cast<std::size_t>(k)]);
      row.insert(row.end(), nodes.begin() + start[c], nodes.begin() + start[c + 1]);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    rows.nodes.insert(rows.nodes.end(), row.begin(), row.end());
    rows.start[j + 1] = static_cast<int>(rows.nodes.size());
  }
  return rows;
}

}  // namespace tissuesim
