// SPDX-License-Identifier: Apache-2.0
#pragma once
// A continuum reference's forces kept in a file, so that a slow FEM solve (minutes) is done once
// for given inputs: organ-poke's --fem-cache. The file is CSV,
//
//   # organ-poke fem reference, key 0123456789abcdef
//   depth_mm,fem_force_n
//   1,0.0327...
//
// The key is a hash of everything the reference depends on (FemReferenceKey): a file whose key
// differs, or that lacks a depth, is not used, and the reference is solved again.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tissuesim::app {

/// Accumulates the inputs of a reference into a 64-bit FNV-1a key.
class FemReferenceKey {
 public:
  /// Bumped whenever the reference's solver or setup changes what it computes.
  static constexpr std::uint64_t kSolverVersion = 1;

  FemReferenceKey();
  void addNumber(double value);
  void addText(const std::string& text);
  std::uint64_t value() const { return m_hash; }

 private:
  void addBytes(const void* data, std::size_t size);
  std::uint64_t m_hash;
};

/// The forces at `depths_mm` from `path` if it holds them under `key`; nothing when the file is
/// absent, has another key or lacks a depth (`why` then says which). @throws CommandError
/// naming the file and line when it exists but is not such a file.
std::optional<std::vector<double>> readFemForceCache(const std::string& path, std::uint64_t key,
                                                     const std::vector<double>& depths_mm,
                                                     std::string& why);

/// Writes the forces at `depths_mm` under `key`, keeping the file's other depths when it already
/// holds forces under the same key. @throws CommandError when it cannot.
void writeFemForceCache(const std::string& path, std::uint64_t key,
                        const std::vector<double>& depths_mm, const std::vector<double>& force_N);

}  // namespace tissuesim::app
