// SPDX-License-Identifier: Apache-2.0
#pragma once
// Makes sure X is there for VTK (Debian's VTK 9.1 renders through X only): with DISPLAY set,
// nothing to do; without, a private Xvfb is started on a free display number (Xvfb's
// -displayfd tells which), DISPLAY is set for this process, and the server is stopped when the
// object goes. Rendering is then Mesa's llvmpipe (software), which makes images the same on
// every machine with the same Mesa.

#include <sys/types.h>
#include <string>

namespace tissuesim::app {

/// Mesa's software renderer (llvmpipe) takes every core by default; this sets LP_NUM_THREADS
/// (unless the user has) to one fewer than the machine has, so drawing leaves the physics
/// thread a core. Call before the first OpenGL context. Hardware drivers ignore it.
void leaveACoreForPhysics();

class HeadlessDisplay {
 public:
  /// Ensures a display. @throws CommandError with what to install or run when it cannot.
  /// @param isQuiet no "started Xvfb" line on stderr.
  explicit HeadlessDisplay(bool isQuiet = false);
  ~HeadlessDisplay();
  HeadlessDisplay(const HeadlessDisplay&) = delete;
  HeadlessDisplay& operator=(const HeadlessDisplay&) = delete;

  bool startedXvfb() const { return m_server > 0; }
  const std::string& display() const { return m_display; }

 private:
  pid_t m_server = -1;
  std::string m_display;
};

}  // namespace tissuesim::app
