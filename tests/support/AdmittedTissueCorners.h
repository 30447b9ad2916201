// SPDX-License-Identifier: Apache-2.0
#pragma once
// The corners of the tissue file's admitted ranges (docs/tissue-file.md), as tissue-file JSON:
// what the material tests and the simulation tests each run every admitted extreme through.

#include <string>
#include <vector>

namespace tissuesim::test {

struct TissueCorner {
  const char* what;
  double mu_kpa, N, A1_kpa, A2_kpa, f, b, C_kpa;
};

inline std::string tissueJson(const TissueCorner& c) {
  return "{\"mu_kpa\": " + std::to_string(c.mu_kpa) + ", \"N\": " + std::to_string(c.N) +
         ", \"A1_kpa\": " + std::to_string(c.A1_kpa) + ", \"A2_kpa\": " + std::to_string(c.A2_kpa) +
         ", \"f\": " + std::to_string(c.f) + ", \"b\": " + std::to_string(c.b) +
         ", \"C_kpa\": " + std::to_string(c.C_kpa) + ", \"v_ij_m2\": 3.569e-5}";
}

inline std::vector<TissueCorner> admittedTissueCorners() {
  return {
      {"the paper's liver", 0.1, 1.1974, 9.6754, 7543.6, 0.2755, 3.3389, 9.5273},
      {"every modulus at its bound", 1e6, 1.1974, 1e6, 1e6, 0.5, 3.0, 1e6},
      {"nearly Gaussian (N at its bound)", 0.1, 1e8, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"N = 10^6 (was std::bad_alloc)", 0.1, 1e6, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"barely above locking at rest", 0.1, 1.000001, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"softest network, no fibres", 1e-6, 2.0, 0.0, 0.0, 0.0, 0.0, 1e-6},
      {"all fibre, strongest softening", 0.1, 1.2, 1e6, 1e6, 1.0, 1e6, 1e-6},
  };
}

}  // namespace tissuesim::test
