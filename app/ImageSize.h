// SPDX-License-Identifier: Apache-2.0
#pragma once
// WIDTHxHEIGHT on the command line (--size of snapshot and of the frame benchmark).

#include <string>

namespace tissuesim::app {

struct ImageSize {
  int width = 0;
  int height = 0;
};

/// @throws CommandError naming `option` unless text is WxH with both in 16 .. 8192.
ImageSize parseImageSize(const std::string& text, const std::string& option);

/// @throws CommandError naming `option` unless `path` ends in .png and can be written (checked
/// before any work or display is started, so a typo fails at once with one line).
void checkPngOutput(const std::string& path, const std::string& option);

}  // namespace tissuesim::app
