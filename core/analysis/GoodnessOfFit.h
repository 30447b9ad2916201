// SPDX-License-Identifier: Apache-2.0
#pragma once
// Figures of merit for comparing a model's curve with a reference curve.

#include <span>

namespace tissuesim {

/// R^2 = 1 - sum (y_i - m_i)^2 / sum (y_i - mean(y))^2 of `model` against `reference`
/// (same length, at least 2 points). 1 for a perfect match; can be negative.
double coefficientOfDetermination(std::span<const double> reference, std::span<const double> model);

/// The slope k minimising sum (y_i - k x_i)^2 (a line through the origin): sum x y / sum x^2.
double slopeThroughOrigin(std::span<const double> x, std::span<const double> y);

}  // namespace tissuesim
