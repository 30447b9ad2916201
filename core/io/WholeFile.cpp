// SPDX-License-Identifier: Apache-2.0
#include "io/WholeFile.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace tissuesim {
namespace {

std::filesystem::path partialOf(const std::filesystem::path& path) {
  return std::filesystem::path(path.string() + ".partial");
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::filesystem::path& partial,
                       const std::string& reason) {
  std::error_code ignored;
  std::filesystem::remove(partial, ignored);
  throw std::runtime_error("cannot write " + path.string() + " (" + reason + ")");
}

void moveIntoPlace(const std::filesystem::path& path, const std::filesystem::path& partial) {
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) fail(path, partial, error.message());
}

}  // namespace

void writeWholeFile(const std::filesystem::path& path, std::string_view bytes) {
  const std::filesystem::path partial = partialOf(path);
  std::FILE* file = std::fopen(partial.c_str(), "wb");
  if (file == nullptr) fail(path, partial, std::strerror(errno));
  const std::size_t written = std::fwrite(bytes.data(), 1, bytes.size(), file);
  int error = written == bytes.size() ? 0 : errno;
  if (std::fflush(file) != 0 && error == 0) error = errno;
  if (std::fclose(file) != 0 && error == 0) error = errno;
  if (written != bytes.size() || error != 0)
    fail(path, partial, std::strerror(error != 0 ? error : EIO));
  moveIntoPlace(path, partial);
}

void writeWholeFileWith(const std::filesystem::path& path,
                        const std::function<bool(const std::filesystem::path&)>& writeTo) {
  const std::filesystem::path partial = partialOf(path);
  errno = 0;
  if (!writeTo(partial)) fail(path, partial, errno != 0 ? std::strerror(errno) : "write failed");
  moveIntoPlace(path, partial);
}

}  // namespace tissuesim
