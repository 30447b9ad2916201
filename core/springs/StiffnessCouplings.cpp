// SPDX-License-Identifier: Apache-2.0
#include "springs/StiffnessCouplings.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tissuesim {

Eigen::Matrix2Xi stiffnessCouplings(const SpringMesh& mesh, const VolumeCells* cells) {
  if (cells == nullptr) return mesh.springs;
  return stiffnessCouplings(mesh, cells->nodePairs());
}

Eigen::Matrix2Xi stiffnessCouplings(const SpringMesh& mesh, const Eigen::Matrix2Xi& others) {
  const Eigen::Matrix2Xi& springs = mesh.springs;
  const auto key = [](int a, int b) {
    return static_cast<std::uint64_t>(std::min(a, b)) << 32 |
           static_cast<std::uint64_t>(std::max(a, b));
  };
  std::vector<std::uint64_t> springKeys;
  springKeys.reserve(static_cast<std::size_t>(springs.cols()));
  for (Eigen::Index s = 0; s < springs.cols(); ++s)
    springKeys.push_back(key(springs(0, s), springs(1, s)));
  std::sort(springKeys.begin(), springKeys.end());
  std::vector<std::uint64_t> extraKeys;
  for (Eigen::Index p = 0; p < others.cols(); ++p) {
    const std::uint64_t k = key(others(0, p), others(1, p));
    if (!std::binary_search(springKeys.begin(), springKeys.end(), k)) extraKeys.push_back(k);
  }
  std::sort(extraKeys.begin(), extraKeys.end());
  extraKeys.erase(std::unique(extraKeys.begin(), extraKeys.end()), extraKeys.end());
  Eigen::Matrix2Xi couplings(2, springs.cols() + static_cast<Eigen::Index>(extraKeys.size()));
  couplings.leftCols(springs.cols()) = springs;
  for (std::size_t k = 0; k < extraKeys.size(); ++k) {
    const Eigen::Index column = springs.cols() + static_cast<Eigen::Index>(k);
    couplings(0, column) = static_cast<int>(extraKeys[k] >> 32);
    couplings(1, column) = static_cast<int>(extraKeys[k] & 0xffffffffu);
  }
  return couplings;
}

}  // namespace tissuesim
