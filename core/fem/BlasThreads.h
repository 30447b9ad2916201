// SPDX-License-Identifier: Apache-2.0
#pragma once
// The BLAS's own threads (CHOLMOD's dense blocks run on them). Debian's OpenBLAS starts one per
// core and its workers spin while they wait for work: where the cores are shared with a real-time
// loop and the window's drawing, a factorisation that takes tens of milliseconds alone can stall
// for most of a second. Its threaded kernels also round differently from its serial ones, so a
// result near a threshold can depend on the thread count the environment sets. An FEM that runs
// beside such work, or must give the same result everywhere, keeps the BLAS to one thread.

namespace tissuesim {

/// While any of these lives, the process's BLAS runs on one thread where it is OpenBLAS (found at
/// run time, so any BLAS Debian's alternatives select works; nothing where it has no such
/// control); the last to go gives back the thread count the first found.
class OneBlasThread {
 public:
  OneBlasThread();
  ~OneBlasThread();
  OneBlasThread(const OneBlasThread&) = delete;
  OneBlasThread& operator=(const OneBlasThread&) = delete;

 private:
  bool m_isKept = false;  ///< the BLAS has the control (OpenBLAS), and this one counts
};

}  // namespace tissuesim
