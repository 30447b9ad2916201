// SPDX-License-Identifier: Apache-2.0
#pragma once
// What every fuzz target shares: the input as a file (the parsers read files by name), and the
// rule that only the project's own one-line errors may come out of a parser. Anything else (an
// exception from a library, a crash, a sanitizer report) is a finding: it aborts.

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace tissuesim::fuzz {

/// The files asFile() has written, removed when the process ends (a fuzz run leaves none behind).
class WrittenFiles {
 public:
  ~WrittenFiles() {
    for (const std::filesystem::path& path : m_paths) {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  }
  void add(const std::filesystem::path& path) {
    if (std::find(m_paths.begin(), m_paths.end(), path) == m_paths.end()) m_paths.push_back(path);
  }

 private:
  std::vector<std::filesystem::path> m_paths;
};

/// The input written to a file of this process's with the given extension.
inline std::filesystem::path asFile(const std::uint8_t* data, std::size_t size,
                                    const std::string& extension) {
  static WrittenFiles written;
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("tissuesim-fuzz-" + std::to_string(::getpid()) + extension);
  written.add(path);
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs parse(); the exception types listed are the parser's contract, anything else aborts.
template <typename... Allowed, typename Parse>
void expectOnlyOwnErrors(const Parse& parse) {
  try {
    parse();
  } catch (const std::exception& error) {
    const bool isAllowed = (... || (dynamic_cast<const Allowed*>(&error) != nullptr));
    if (!isAllowed) {
      std::fprintf(stderr, "finding: an error outside the parser's contract: %s\n", error.what());
      std::abort();
    }
  }
}

}  // namespace tissuesim::fuzz
