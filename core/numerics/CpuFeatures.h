// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the CPU the program runs on can do, asked once: the SIMD kernels (the batched spring law,
// CG's product) take their AVX+FMA path only where this says so, and a portable one elsewhere.

namespace tissuesim {

/// True on an x86-64 CPU with both AVX and FMA (decided on the first call).
bool hasAvxAndFma();

}  // namespace tissuesim
