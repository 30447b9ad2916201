// SPDX-License-Identifier: Apache-2.0
#pragma once
// Node-wise passes over vectors of #V nodes (residuals, external forces, predictor and velocity
// updates), cut into kNodeRanges fixed ranges of [0, count):
//
//   range r = [count r / kNodeRanges, count (r + 1) / kNodeRanges)
//
// The ranges depend on the node count alone, never on the thread count, so per-range partial
// results (a maximum, a sum of squares) combined in range order are bit-identical on 1, 2 or 4
// threads. Small meshes run the ranges in order on the caller: a pass over the liver's 1,100
// nodes takes about a microsecond, less than a hand-off to the pool; at 100k springs (15,600
// nodes) each such pass took 40-60 us on one thread, and ten of them a step were a sixth of the
// two-thread step's time.

#include <array>

#include <Eigen/Core>

#include "parallel/ForkJoinPool.h"

namespace tissuesim {

constexpr int kNodeRanges = 4;
/// From this many nodes on, node-wise passes run on the pool.
constexpr Eigen::Index kParallelNodePassMinimum = 8192;

/// Per-range flags of a pass (whether each range held only finite values, say).
using NodeRangeFlags = std::array<bool, kNodeRanges>;

/// Whether every range's flag is set.
inline bool allRanges(const NodeRangeFlags& flags) {
  for (const bool flag : flags) {
    if (!flag) return false;
  }
  return true;
}

/// First node of range r (r = kNodeRanges: count).
inline Eigen::Index nodeRangeStart(Eigen::Index count, int r) { return count * r / kNodeRanges; }

/// Calls task(r, begin, end) once for every range r, on `pool` when there is one and the pass
/// has at least `poolMinimum` nodes, else in order on the caller. A pass that does more per node
/// than read a column or two (a gather over each node's cells) lowers the minimum. The same
/// rules as ForkJoinPool::run: the task must not throw or use the pool itself.
template <typename Task>
void forEachNodeRange(ForkJoinPool* pool, Eigen::Index count, const Task& task,
                      Eigen::Index poolMinimum = kParallelNodePassMinimum) {
  const auto range = [&](int r) {
    task(r, nodeRangeStart(count, r), nodeRangeStart(count, r + 1));
  };
  runParts(count >= poolMinimum ? pool : nullptr, kNodeRanges, range);
}

}  // namespace tissuesim
