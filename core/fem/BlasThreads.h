// SPDX-License-Identifier: Apache-2.0
#pragma once
// The BLAS's own threads (CHOLMOD's dense blocks run on them). Debian's OpenBLAS starts one per
// core and its workers spin while they wait for work: where the cores are shared with a real-time
// loop and the window's drawing, a factorisation that takes tens of milliseconds alone can stall
// for most of a second. A caller whose FEM runs beside such work keeps the BLAS to one thread.

namespace tissuesim {

/// Sets the process's BLAS to one thread where it is OpenBLAS (found at run time, so any BLAS
/// Debian's alternatives select works); @returns false where the BLAS has no such control.
bool keepBlasToOneThread();

}  // namespace tissuesim
