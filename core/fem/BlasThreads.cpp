// SPDX-License-Identifier: Apache-2.0
#include "fem/BlasThreads.h"

#include <dlfcn.h>

#include <mutex>

namespace tissuesim {
namespace {

using SetThreads = void (*)(int);
using GetThreads = int (*)();

/// The owners alive and the count the first of them found: the last to go gives it back, in
/// whatever order they go (a scene's body is made anew before the old one goes).
struct Owners {
  std::mutex mutex;
  int alive = 0;
  int found = 0;
};

Owners& owners() {
  static Owners instance;
  return instance;
}

SetThreads setThreads() {
  return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
}

GetThreads getThreads() {
  return reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
}

}  // namespace

OneBlasThread::OneBlasThread() {
  const SetThreads set = setThreads();
  const GetThreads get = getThreads();
  if (set == nullptr || get == nullptr) return;
  m_isKept = true;
  Owners& all = owners();
  const std::lock_guard<std::mutex> lock(all.mutex);
  if (all.alive++ == 0) {
    all.found = get();
    set(1);
  }
}

OneBlasThread::~OneBlasThread() {
  if (!m_isKept) return;
  Owners& all = owners();
  const std::lock_guard<std::mutex> lock(all.mutex);
  if (--all.alive == 0) setThreads()(all.found);
}

}  // namespace tissuesim
