// SPDX-License-Identifier: Apache-2.0
#include "springs/StiffnessCouplings.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tissuesim {

Eigen::Matrix2Xi stiffnessCouplings(const SpringMesh& mesh, const VolumeCells* cells) {
  const Eigen::Matrix2Xi& springs = mesh.springs;
  if (cells == nullptr) return springs;
  const auto key = [](int a, int b) {
    return static_cast<std::uint64_t>(std::min(a, b)) << 32 |
           static_cast<std::uint64_t>(std::max(a, b));
  };
  std::vector<std::uint64_t> springKeys;
  springKeys.reserve(static_cast<std::size_t>(springs.cols()));
  for (Eigen::Index s = 0; s < springs.cols(); ++s)
    springKeys.push_back(key(springs(0, s), springs(1, s)));
  std::sort(springKeys.begin(), springKeys.end());
  const Eigen::Matrix2Xi cellPairs = cells->nodePairs();
  std::vector<Eigen::Index> extra;
  for (Eigen::Index p = 0; p < cellPairs.cols(); ++p) {
    if (!std::binary_search(springKeys.begin(), springKeys.end(),
                            key(cellPairs(0, p), cellPairs(1, p))))
      extra.push_back(p);
  }
  Eigen::Matrix2Xi couplings(2, springs.cols() + static_cast<Eigen::Index>(extra.size()));
  couplings.leftCols(springs.cols()) = springs;
  for (std::size_t k = 0; k < extra.size(); ++k)
    couplings.col(springs.cols() + static_cast<Eigen::Index>(k)) = cellPairs.col(extra[k]);
  return couplings;
}

}  // namespace tissuesim
