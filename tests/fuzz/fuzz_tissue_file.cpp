// SPDX-License-Identifier: Apache-2.0
// The tissue file's parser: any bytes give parameters or a TissueFileError, and the parameters
// it accepts give finite tables (docs/tissue-file.md's admissible ranges).
#include <cmath>
#include <string_view>

#include "fuzz/FuzzInput.h"
#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/TissueFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  fuzz::expectOnlyOwnErrors<TissueFileError>([&] {
    const TissueParameters parameters =
        parseTissueJson(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
    const StrainEnergy energy(parameters);
    if (!std::isfinite(energy.initialShearModulus()) || !(energy.initialShearModulus() > 0.0)) {
      std::fprintf(stderr, "finding: an accepted tissue with mu0 %g\n",
                   energy.initialShearModulus());
      std::abort();
    }
  });
  return 0;
}
