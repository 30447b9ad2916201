// SPDX-License-Identifier: Apache-2.0
// The session recording's reader: any bytes give a recording or its one-line error.
#include "fuzz/FuzzInput.h"
#include "sim/SessionRecording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::filesystem::path path = fuzz::asFile(data, size, ".jsonl");
  fuzz::expectOnlyOwnErrors<RecordingError>([&] { readRecording(path); });
  return 0;
}
