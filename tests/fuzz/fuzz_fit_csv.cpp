// SPDX-License-Identifier: Apache-2.0
// The fit's test data (analysis/TensileTestData.h): any bytes give branches of finite stretches
// and stresses, each loading branch rising and each unloading one falling, or a TestDataError.
#include <cmath>

#include "analysis/TensileTestData.h"
#include "fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::filesystem::path path = fuzz::asFile(data, size, ".csv");
  fuzz::expectOnlyOwnErrors<TestDataError>([&] {
    for (const CurveBranch& branch : readTensileTestCsv(path, SpecimenGeometry{50.0, 10.0})) {
      for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
        if (!std::isfinite(branch.stretch[i]) || !(branch.stretch[i] > 0.0) ||
            !std::isfinite(branch.stress_Pa[i]))
          std::abort();
      }
    }
  });
  return 0;
}
