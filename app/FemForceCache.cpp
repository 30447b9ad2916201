// SPDX-License-Identifier: Apache-2.0
#include "app/FemForceCache.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/CommandError.h"
#include "app/OutputFile.h"

namespace tissuesim::app {
namespace {

constexpr const char* kKeyLine = "# organ-poke fem reference, key ";
constexpr const char* kHeader = "depth_mm,fem_force_n";

std::string hex(std::uint64_t key) {
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, key);
  return text;
}

/// A cache file's key (as written) and its (depth, force) rows. @throws CommandError naming the
/// file and line when it is not such a file.
struct CacheContents {
  std::string key;
  std::vector<std::pair<double, double>> rows;
};

CacheContents readContents(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw CommandError(path + ": cannot be read");
  const auto bad = [&](int line, const std::string& what) {
    return CommandError(path + ":" + std::to_string(line) + ": " + what);
  };
  CacheContents contents;
  std::string line;
  if (!std::getline(in, line) || line.rfind(kKeyLine, 0) != 0)
    throw bad(1, std::string("expected a first line '") + kKeyLine + "KEY'");
  contents.key = line.substr(std::strlen(kKeyLine));
  if (!std::getline(in, line) || line != kHeader)
    throw bad(2, std::string("expected the header '") + kHeader + "'");
  for (int number = 3; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    double depth = 0.0, force = 0.0;
    char comma = 0;
    if (!(fields >> depth >> comma >> force) || comma != ',' || !std::isfinite(depth) ||
        !std::isfinite(force) || !(fields >> std::ws).eof())
      throw bad(number, "expected 'depth_mm,fem_force_n', two finite numbers");
    contents.rows.emplace_back(depth, force);
  }
  return contents;
}

bool isSameDepth(double a_mm, double b_mm) {
  return std::abs(a_mm - b_mm) <= 1e-9 * std::max(1.0, std::abs(b_mm));
}

}  // namespace

FemReferenceKey::FemReferenceKey() : m_hash(14695981039346656037ull) {
  addNumber(static_cast<double>(kSolverVersion));
}

void FemReferenceKey::addBytes(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    m_hash ^= bytes[i];
    m_hash *= 1099511628211ull;
  }
}

void FemReferenceKey::addNumber(double value) {
  // Printed to the bit, so that the key does not depend on the machine's byte order.
  char text[32];
  const int length = std::snprintf(text, sizeof text, "%.17g;", value);
  addBytes(text, static_cast<std::size_t>(length));
}

void FemReferenceKey::addText(const std::string& text) {
  addBytes(text.data(), text.size());
  addBytes(";", 1);
}

std::optional<std::vector<double>> readFemForceCache(const std::string& path, std::uint64_t key,
                                                     const std::vector<double>& depths_mm,
                                                     std::string& why) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    why = "it does not exist yet";
    return std::nullopt;
  }
  const CacheContents contents = readContents(path);
  if (contents.key != hex(key)) {
    why = "it holds a reference for other inputs (scene, tissue, FEM mesh or solver)";
    return std::nullopt;
  }
  std::vector<double> forces;
  for (const double depth : depths_mm) {
    const auto found = std::find_if(contents.rows.begin(), contents.rows.end(),
                                    [&](const auto& row) { return isSameDepth(row.first, depth); });
    if (found == contents.rows.end()) {
      why = "it has no force at " + std::to_string(depth) + " mm";
      return std::nullopt;
    }
    forces.push_back(found->second);
  }
  return forces;
}

void writeFemForceCache(const std::string& path, std::uint64_t key,
                        const std::vector<double>& depths_mm, const std::vector<double>& force_N) {
  std::vector<std::pair<double, double>> rows;
  for (std::size_t d = 0; d < depths_mm.size() && d < force_N.size(); ++d)
    rows.emplace_back(depths_mm[d], force_N[d]);
  // The same inputs' other depths stay: a poke to other depths adds to the file, not replaces it.
  std::error_code error;
  if (std::filesystem::exists(path, error)) {
    try {
      const CacheContents kept = readContents(path);
      if (kept.key == hex(key)) {
        for (const auto& row : kept.rows) {
          const bool isNew = std::none_of(rows.begin(), rows.end(), [&](const auto& added) {
            return isSameDepth(added.first, row.first);
          });
          if (isNew) rows.push_back(row);
        }
      }
    } catch (const CommandError&) {
      // Not a cache: overwritten.
    }
  }
  std::sort(rows.begin(), rows.end());
  std::string text = kKeyLine + hex(key) + "\n" + kHeader + "\n";
  for (const auto& [depth, force] : rows) {
    char line[64];
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", depth, force);
    text += line;
  }
  writeTextFile(path, "--fem-cache", text);
}

}  // namespace tissuesim::app
