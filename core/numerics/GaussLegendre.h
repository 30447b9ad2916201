// SPDX-License-Identifier: Apache-2.0
#pragma once
// 8-point Gauss-Legendre quadrature on [0, 1]: integral_0^1 g(s) ds ~ sum_k w_k g(s_k), exact for
// polynomials of degree 15.

#include <array>

namespace tissuesim {

inline constexpr std::array<double, 8> kGaussLegendreNodes = {
    0.019855071751231856, 0.10166676129318664, 0.2372337950418355, 0.4082826787521751,
    0.5917173212478249,   0.7627662049581645,  0.8983332387068134, 0.9801449282487681};
inline constexpr std::array<double, 8> kGaussLegendreWeights = {
    0.05061426814518813, 0.11119051722668724, 0.15685332293894363, 0.18134189168918100,
    0.18134189168918100, 0.15685332293894363, 0.11119051722668724, 0.05061426814518813};

}  // namespace tissuesim
