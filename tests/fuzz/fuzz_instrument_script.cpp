// SPDX-License-Identifier: Apache-2.0
// The instrument script's parser: any bytes give a script or its one-line error.
#include <stdexcept>

#include "fuzz/FuzzInput.h"
#include "sim/InstrumentScript.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::filesystem::path path = fuzz::asFile(data, size, ".json");
  fuzz::expectOnlyOwnErrors<std::invalid_argument>([&] { InstrumentScript::load(path); });
  return 0;
}
