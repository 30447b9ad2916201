// SPDX-License-Identifier: Apache-2.0
#include "app/OutputFile.h"

#include <filesystem>
#include <fstream>
#include <system_error>

#include "app/CommandError.h"
#include "io/WholeFile.h"

namespace tissuesim::app {

void checkOutputWritable(const std::string& path, const std::string& option) {
  std::error_code error;
  const bool existed = std::filesystem::exists(path, error);
  // Append mode: an existing file is opened without being truncated.
  if (!std::ofstream(path, std::ios::app)) {
    throw CommandError("cannot write " + option + " " + path +
                       " (no such folder, or no permission to write there)");
  }
  if (!existed) std::filesystem::remove(path, error);
}

void writeTextFile(const std::string& path, const std::string& option, const std::string& text) {
  try {
    writeWholeFile(path, text);
  } catch (const std::runtime_error& error) {
    throw CommandError(option + ": " + error.what());
  }
}

}  // namespace tissuesim::app
