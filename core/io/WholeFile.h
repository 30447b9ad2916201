// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writing an output file whole or not at all: the bytes go to a sibling "NAME.partial", which is
// flushed, closed and then renamed over NAME. A failure on the way (a full disk, a quota, a
// folder that went away) removes the partial file and throws with the system's reason, so an
// export never leaves half a file where a whole one is expected.

#include <filesystem>
#include <functional>
#include <string_view>

namespace tissuesim {

/// @throws std::runtime_error "cannot write PATH (REASON)"; nothing is left at PATH.partial, and
/// PATH is as it was.
void writeWholeFile(const std::filesystem::path& path, std::string_view bytes);

/// The same for a writer that takes a file name (VTK's): writeTo(partial) returns whether it
/// wrote the whole file there.
void writeWholeFileWith(const std::filesystem::path& path,
                        const std::function<bool(const std::filesystem::path&)>& writeTo);

}  // namespace tissuesim
