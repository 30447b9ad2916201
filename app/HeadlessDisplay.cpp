// SPDX-License-Identifier: Apache-2.0
#include "app/HeadlessDisplay.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/CommandError.h"

namespace tissuesim::app {
namespace {

std::string findOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string paths = path != nullptr ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= paths.size()) {
    const std::size_t end = std::min(paths.find(':', start), paths.size());
    const std::filesystem::path candidate =
        std::filesystem::path(paths.substr(start, end - start)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

}  // namespace

void leaveACoreForPhysics() {
  if (std::getenv("LP_NUM_THREADS") != nullptr) return;
  const unsigned cores = std::thread::hardware_concurrency();
  ::setenv("LP_NUM_THREADS", std::to_string(cores > 1 ? cores - 1 : 1).c_str(), 0);
}

HeadlessDisplay::HeadlessDisplay(bool isQuiet) {
  if (const char* display = std::getenv("DISPLAY"); display != nullptr && *display != '\0') {
    m_display = display;
    return;
  }
  const std::string xvfb = findOnPath("Xvfb");
  if (xvfb.empty()) {
    throw CommandError(
        "no X display (DISPLAY is unset) and Xvfb is not installed: install it with "
        "'sudo apt-get install xvfb xauth', or run under an X server");
  }
  int pipeFds[2];
  if (::pipe2(pipeFds, O_CLOEXEC) != 0) throw CommandError("cannot start Xvfb: pipe failed");
  const pid_t child = ::fork();
  if (child < 0) throw CommandError("cannot start Xvfb: fork failed");
  if (child == 0) {
    // Xvfb writes the display number it picked to the pipe; keep its fd open across exec.
    ::fcntl(pipeFds[1], F_SETFD, 0);
    const int devNull = ::open("/dev/null", O_RDWR);
    if (devNull >= 0) {
      ::dup2(devNull, STDIN_FILENO);
      ::dup2(devNull, STDOUT_FILENO);
      ::dup2(devNull, STDERR_FILENO);
    }
    const std::string fd = std::to_string(pipeFds[1]);
    ::execl(xvfb.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1920x1200x24",
            "-nolisten", "tcp", "-noreset", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(pipeFds[1]);
  m_server = child;
  // Wait (at most 10 s) for the number; a server that exits early has failed.
  std::string number;
  pollfd poller{pipeFds[0], POLLIN, 0};
  while (number.find('\n') == std::string::npos) {
    if (::poll(&poller, 1, 10000) <= 0) break;
    char buffer[32];
    const ssize_t got = ::read(pipeFds[0], buffer, sizeof buffer);
    if (got <= 0) break;
    number.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(pipeFds[0]);
  while (!number.empty() && (number.back() == '\n' || number.back() == ' ')) number.pop_back();
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos) {
    ::kill(m_server, SIGTERM);
    ::waitpid(m_server, nullptr, 0);
    m_server = -1;
    throw CommandError("no X display (DISPLAY is unset) and the private Xvfb (" + xvfb +
                       ") did not start; try: xvfb-run -a tissuesim ...");
  }
  m_display = ":" + number;
  ::setenv("DISPLAY", m_display.c_str(), 1);
  if (!isQuiet) {
    std::fprintf(stderr,
                 "tissuesim: no DISPLAY; rendering on a private Xvfb at %s (Mesa llvmpipe)\n",
                 m_display.c_str());
  }
}

HeadlessDisplay::~HeadlessDisplay() {
  if (m_server > 0) {
    ::kill(m_server, SIGTERM);
    ::waitpid(m_server, nullptr, 0);
    ::unsetenv("DISPLAY");
  }
}

}  // namespace tissuesim::app
