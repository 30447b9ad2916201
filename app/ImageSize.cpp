// SPDX-License-Identifier: Apache-2.0
#include "app/ImageSize.h"

#include <charconv>

#include "app/CommandError.h"
#include "app/OutputFile.h"

namespace tissuesim::app {

ImageSize parseImageSize(const std::string& text, const std::string& option) {
  const auto fail = [&] {
    return CommandError(option + " '" + text +
                        "': expected WIDTHxHEIGHT in pixels, each from 16 to 8192");
  };
  const std::size_t x = text.find('x');
  if (x == std::string::npos) throw fail();
  ImageSize size;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto first = std::from_chars(begin, begin + x, size.width);
  const auto second = std::from_chars(begin + x + 1, end, size.height);
  if (first.ec != std::errc() || first.ptr != begin + x || second.ec != std::errc() ||
      second.ptr != end || size.width < 16 || size.height < 16 || size.width > 8192 ||
      size.height > 8192) {
    throw fail();
  }
  return size;
}

void checkPngOutput(const std::string& path, const std::string& option) {
  if (path.size() < 5 || path.substr(path.size() - 4) != ".png") {
    throw CommandError(option + " " + path + ": expected a file name ending in .png");
  }
  checkOutputWritable(path, option);
}

}  // namespace tissuesim::app
