// SPDX-License-Identifier: Apache-2.0
#pragma once
// A user-facing failure of a subcommand: main prints its one-line message and exits non-zero.

#include <stdexcept>

namespace tissuesim::app {

class CommandError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tissuesim::app
