// SPDX-License-Identifier: Apache-2.0
#pragma once
// The kernel of NodeBlockMatrix's product y = A x, rows of a range of nodes (3 rows each).
//
// Storage (NodeBlockMatrix): node j's three columns 3j .. 3j+2 are consecutive, each 3 n_j long
// (n_j = j's neighbours, j included, sorted), rows 3i .. 3i+2 of each neighbour i contiguous. By
// symmetry row 3j+c is column 3j+c, so
//
//   y_(3j+c) = column(3j+c) . g_j,   g_j = (x_i0, x_i1, ...)  (3 n_j, j's neighbours' x)     (1)
//
// three dot products of length 3 n_j with one gathered vector: contiguous loads and
// multiply-adds that SIMD units take 2 or 4 at a time. Two kernels: AVX with FMA where the CPU
// has both (chosen once, at run time), else SSE2, which every x86-64 has. They round
// differently (FMA, 4 or 2 partial sums), so a run is bit-identical to another on the same kind
// of CPU only; neither kernel's result depends on how the nodes are cut into ranges.

#include <Eigen/Core>

namespace tissuesim {

/// What the kernels read of a NodeBlockMatrix (pointers into its arrays).
struct NodeBlockRows {
  const double* values;       ///< Eigen's value array
  const int* outer;           ///< Eigen's column starts (3#V + 1)
  const int* neighbourStart;  ///< #V + 1
  const int* neighbourIndex;  ///< per node, its neighbours, sorted, itself included
};

/// Rows 3j .. 3j+2 of y = A x for j in [begin, end), by (1), with the kernel chosen for this CPU.
void multiplyNodeRows(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                      const double* x, double* y);

/// The two kernels, for tests; the AVX one only where hasAvxAndFma() (numerics/CpuFeatures.h).
void multiplyNodeRowsSse2(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                          const double* x, double* y);
void multiplyNodeRowsAvxFma(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                            const double* x, double* y);

}  // namespace tissuesim
