// SPDX-License-Identifier: Apache-2.0
#pragma once
// Large blocks go back to the system when freed. Each FEM update at its own rate allocates the
// body's response to its contact (3#V by 3m, m the contact's nodes) and CHOLMOD's copy of its
// solve, megabytes whose size changes with every contact. glibc raises its mmap threshold to the
// largest block freed, after which such blocks come from the heaps and stay resident there as
// the contacts' sizes wander: a long session's memory grows by megabytes it no longer uses.
// A fixed threshold (and a trim threshold to match) keeps them mapped and returned.

namespace tissuesim::app {

/// Sets the process's allocator so that blocks of half a megabyte and more are mapped and
/// returned on free (glibc's M_MMAP_THRESHOLD, M_TRIM_THRESHOLD); nothing elsewhere.
void returnLargeBlocksToTheSystem();

}  // namespace tissuesim::app
