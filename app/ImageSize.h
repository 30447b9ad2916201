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

}  // namespace tissuesim::app
