// SPDX-License-Identifier: Apache-2.0
#pragma once
// Output files named on the command line, checked before any work starts: a typo in a folder
// fails at once with one line, not after a run of seconds or minutes.

#include <string>

namespace tissuesim::app {

/// @throws CommandError naming `option` and `path` unless `path` can be opened for writing. A
/// file that did not exist before is removed again; an existing one is left as it was.
void checkOutputWritable(const std::string& path, const std::string& option);

/// Writes `text` to `path`. @throws CommandError naming `option` and `path` when it cannot.
void writeTextFile(const std::string& path, const std::string& option, const std::string& text);

}  // namespace tissuesim::app
