// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeCells.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>

namespace tissuesim {

namespace {

/// The nodes of tet t at its bounding box's lowest and highest corners, when it has both (a Kuhn
/// tet: its cube's main diagonal); {-1, -1} otherwise.
std::pair<int, int> diagonalOf(const Eigen::Matrix3Xd& rest, const Eigen::Matrix4Xi& tets,
                               Eigen::Index t) {
  Eigen::Vector3d low = rest.col(tets(0, t));
  Eigen::Vector3d high = low;
  for (int i = 1; i < 4; ++i) {
    low = low.cwiseMin(rest.col(tets(i, t)));
    high = high.cwiseMax(rest.col(tets(i, t)));
  }
  int lowNode = -1, highNode = -1;
  for (int i = 0; i < 4; ++i) {
    if (rest.col(tets(i, t)) == low) lowNode = tets(i, t);
    if (rest.col(tets(i, t)) == high) highNode = tets(i, t);
  }
  if (lowNode < 0 || highNode < 0) return {-1, -1};
  return {lowNode, highNode};
}

/// Parity of the permutation taking `from` to `to` (the same four nodes): +1 even, -1 odd.
int permutationSign(const std::array<int, 4>& from, const std::array<int, 4>& to) {
  std::array<int, 4> position{};
  for (std::size_t i = 0; i < 4; ++i) {
    position[i] = static_cast<int>(std::find(from.begin(), from.end(), to[i]) - from.begin());
  }
  int sign = 1;
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t j = i + 1; j < 4; ++j) sign *= position[i] > position[j] ? -1 : 1;
  }
  return sign;
}

/// Cell c's corners around its diagonal (VolumeCells::cubeSlots), its tets reordered to match,
/// when it is six tets sharing the diagonal (low, high) whose other two nodes chain, each tet
/// turned the same way, into one loop of six corners. Leaves the cell as it is otherwise.
void orderCubeAroundItsDiagonal(VolumeCells& cells, const Eigen::Matrix4Xi& tets, Eigen::Index c,
                                int low, int high) {
  const auto begin = static_cast<std::size_t>(cells.tetStart[static_cast<std::size_t>(c)]);
  if (cells.tetStart[static_cast<std::size_t>(c) + 1] - static_cast<int>(begin) != 6) return;
  // Each tet as a step a -> b around the diagonal, turned so that (low, a, b, high) is an even
  // permutation of the tet's own order: its volume is then d . (h_a x h_b) / 6 exactly.
  std::array<std::array<int, 2>, 6> steps{};
  for (std::size_t k = 0; k < 6; ++k) {
    const int t = cells.tets[begin + k];
    const std::array<int, 4> own{tets(0, t), tets(1, t), tets(2, t), tets(3, t)};
    std::array<int, 2> others{};
    std::size_t count = 0;
    for (const int node : own) {
      if (node == low || node == high) continue;
      if (count == 2) return;
      others[count++] = node;
    }
    if (count != 2) return;
    if (permutationSign(own, {low, others[0], others[1], high}) < 0)
      std::swap(others[0], others[1]);
    steps[k] = others;
  }
  // Walk the loop from the first step: each corner must start exactly one step.
  std::array<int, 6> corners{};
  std::array<int, 6> order{};
  std::array<bool, 6> taken{};
  int corner = steps[0][0];
  for (std::size_t k = 0; k < 6; ++k) {
    std::size_t next = 6;
    for (std::size_t s = 0; s < 6; ++s) {
      if (!taken[s] && steps[s][0] == corner) next = s;
    }
    if (next == 6) return;
    taken[next] = true;
    corners[k] = corner;
    order[k] = cells.tets[begin + next];
    corner = steps[next][1];
  }
  if (corner != corners[0]) return;
  const auto slotOf = [&](int node) {
    int slot = 0;
    while (cells.nodes(slot, c) != node) ++slot;
    return slot;
  };
  cells.cubeSlots(0, c) = slotOf(low);
  for (std::size_t k = 0; k < 6; ++k) {
    cells.cubeSlots(static_cast<Eigen::Index>(k) + 1, c) = slotOf(corners[k]);
    cells.tets[begin + k] = order[k];
  }
  cells.cubeSlots(7, c) = slotOf(high);
}

}  // namespace

VolumeCells groupTetsIntoCells(const Eigen::Matrix3Xd& restPositions_m,
                               const Eigen::Matrix4Xi& tets,
                               const Eigen::VectorXd& tetRestVolume_m3) {
  const Eigen::Index tetCount = tets.cols();
  std::vector<std::pair<int, int>> diagonals(static_cast<std::size_t>(tetCount));
  for (Eigen::Index t = 0; t < tetCount; ++t)
    diagonals[static_cast<std::size_t>(t)] = diagonalOf(restPositions_m, tets, t);
  // Tets with one diagonal side by side, in tet order within it.
  std::vector<int> order(static_cast<std::size_t>(tetCount));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return diagonals[static_cast<std::size_t>(a)] < diagonals[static_cast<std::size_t>(b)];
  });

  // Groups of one diagonal, each cut where its nodes would pass kMaxNodes.
  std::vector<std::vector<int>> groups;
  std::vector<int> groupNodes;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int t = order[k];
    const std::pair<int, int>& diagonal = diagonals[static_cast<std::size_t>(t)];
    const bool sameCube = k > 0 && diagonal.first >= 0 &&
                          diagonal == diagonals[static_cast<std::size_t>(order[k - 1])];
    std::vector<int> merged = sameCube ? groupNodes : std::vector<int>{};
    for (int i = 0; i < 4; ++i) merged.push_back(tets(i, t));
    std::sort(merged.begin(), merged.end());
    merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
    if (sameCube && static_cast<int>(merged.size()) <= VolumeCells::kMaxNodes) {
      groups.back().push_back(t);
      groupNodes = std::move(merged);
    } else {
      groups.push_back({t});
      groupNodes.clear();
      for (int i = 0; i < 4; ++i) groupNodes.push_back(tets(i, t));
      std::sort(groupNodes.begin(), groupNodes.end());
    }
  }
  // Cells in the order of their first tet: the mesh's own locality.
  std::sort(groups.begin(), groups.end(),
            [](const std::vector<int>& a, const std::vector<int>& b) { return a[0] < b[0]; });

  VolumeCells cells;
  const auto cellCount = static_cast<Eigen::Index>(groups.size());
  cells.nodes.setConstant(VolumeCells::kMaxNodes, cellCount, -1);
  cells.nodeCount.resize(groups.size());
  cells.tetStart.assign(1, 0);
  cells.tets.reserve(static_cast<std::size_t>(tetCount));
  cells.tetSlots.resize(4, tetCount);
  cells.restVolume_m3.setZero(cellCount);
  for (Eigen::Index c = 0; c < cellCount; ++c) {
    int count = 0;
    for (const int t : groups[static_cast<std::size_t>(c)]) {
      cells.tets.push_back(t);
      cells.restVolume_m3[c] += tetRestVolume_m3[t];
      for (int i = 0; i < 4; ++i) {
        const int node = tets(i, t);
        int slot = 0;
        while (slot < count && cells.nodes(slot, c) != node) ++slot;
        if (slot == count) cells.nodes(count++, c) = node;
        cells.tetSlots(i, t) = slot;
      }
    }
    cells.nodeCount[static_cast<std::size_t>(c)] = count;
    cells.tetStart.push_back(static_cast<int>(cells.tets.size()));
  }
  cells.cubeSlots.setConstant(VolumeCells::kMaxNodes, cellCount, -1);
  for (Eigen::Index c = 0; c < cellCount; ++c) {
    const std::pair<int, int>& diagonal =
        diagonals[static_cast<std::size_t>(groups[static_cast<std::size_t>(c)][0])];
    if (diagonal.first >= 0 && cells.nodeCount[static_cast<std::size_t>(c)] == 8)
      orderCubeAroundItsDiagonal(cells, tets, c, diagonal.first, diagonal.second);
  }
  return cells;
}

Eigen::Matrix2Xi VolumeCells::nodePairs() const {
  std::vector<std::uint64_t> pairs;
  for (Eigen::Index c = 0; c < cellCount(); ++c) {
    const int count = nodeCount[static_cast<std::size_t>(c)];
    for (int i = 0; i < count; ++i) {
      for (int j = i + 1; j < count; ++j) {
        const auto a = static_cast<std::uint64_t>(std::min(nodes(i, c), nodes(j, c)));
        const auto b = static_cast<std::uint64_t>(std::max(nodes(i, c), nodes(j, c)));
        pairs.push_back(a << 32 | b);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Eigen::Matrix2Xi out(2, static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    out.col(static_cast<Eigen::Index>(k)) << static_cast<int>(pairs[k] >> 32),
        static_cast<int>(pairs[k] & 0xffffffffu);
  }
  return out;
}

}  // namespace tissuesim
