// SPDX-License-Identifier: Apache-2.0
#pragma once
// This process's memory, as Linux reports it: what `soak` watches for growth and `trade`
// reports per scene.

namespace tissuesim::app {

/// Resident memory now (bytes), from /proc/self/statm; 0 where there is none.
double residentBytes();
/// The most resident memory so far (bytes): /proc/self/status's VmHWM; 0 where there is none.
/// A forked child's starts at its parent's.
double peakResidentBytes();
/// Makes the high-water mark the resident memory now (Linux 4.0 and later: /proc/self/clear_refs).
void resetPeakResident();

}  // namespace tissuesim::app
