// SPDX-License-Identifier: Apache-2.0
#pragma once
// A cubic Hermite spline on a uniform grid: values and slopes given at the nodes
// x_i = origin + i h, i = 0 .. n-1. Inside a cell, with t = (x - x_i) / h in [0, 1],
//
//   y(x) = h00(t) y_i + h10(t) h y'_i + h01(t) y_{i+1} + h11(t) h y'_{i+1}
//
// (h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t, h01 = -2t^3 + 3t^2, h11 = t^3 - t^2).
// The interpolation error is at most h^4/384 max|y''''|, and the interpolant is C^1.
// Lookups cost one multiply, one floor and two adjacent 16-byte loads: no search, no branch
// beyond the clamp that keeps the index inside the table (outside it the end cell's cubic is
// extrapolated, never memory outside the table).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace tissuesim {

/// A value and its derivative at one node (same units as y, y per unit x).
struct HermiteNode {
  double value;
  double slope;
};

class UniformHermiteSpline {
 public:
  UniformHermiteSpline() = default;
  /// @param origin x_0; @param spacing h > 0; @param nodes n >= 2 values and slopes.
  UniformHermiteSpline(double origin, double spacing, std::vector<HermiteNode> nodes)
      : m_origin(origin),
        m_spacing(spacing),
        m_inverseSpacing(1.0 / spacing),
        m_nodes(std::move(nodes)) {}

  double value(double x) const {
    const Cell cell = locate(x);
    const HermiteNode& a = m_nodes[cell.index];
    const HermiteNode& b = m_nodes[cell.index + 1];
    const double t = cell.t;
    const double t2 = t * t;
    const double t3 = t2 * t;
    return (2.0 * t3 - 3.0 * t2 + 1.0) * a.value + (t3 - 2.0 * t2 + t) * m_spacing * a.slope +
           (-2.0 * t3 + 3.0 * t2) * b.value + (t3 - t2) * m_spacing * b.slope;
  }

  /// The interpolant and its exact derivative (the derivative is what Newton needs for a
  /// consistent tangent of the interpolated force).
  HermiteNode valueAndSlope(double x) const {
    const Cell cell = locate(x);
    const HermiteNode& a = m_nodes[cell.index];
    const HermiteNode& b = m_nodes[cell.index + 1];
    const double t = cell.t;
    const double t2 = t * t;
    const double t3 = t2 * t;
    const double value = (2.0 * t3 - 3.0 * t2 + 1.0) * a.value +
                         (t3 - 2.0 * t2 + t) * m_spacing * a.slope +
                         (-2.0 * t3 + 3.0 * t2) * b.value + (t3 - t2) * m_spacing * b.slope;
    const double slope = (6.0 * t2 - 6.0 * t) * m_inverseSpacing * (a.value - b.value) +
                         (3.0 * t2 - 4.0 * t + 1.0) * a.slope + (3.0 * t2 - 2.0 * t) * b.slope;
    return {value, slope};
  }

  double origin() const { return m_origin; }
  double spacing() const { return m_spacing; }
  double inverseSpacing() const { return m_inverseSpacing; }
  std::size_t size() const { return m_nodes.size(); }
  double back() const { return m_origin + m_spacing * static_cast<double>(m_nodes.size() - 1); }
  const std::vector<HermiteNode>& nodes() const { return m_nodes; }

 private:
  struct Cell {
    std::size_t index;
    double t;
  };

  Cell locate(double x) const {
    const double u = (x - m_origin) * m_inverseSpacing;
    const double maxIndex = static_cast<double>(m_nodes.size() - 2);
    const double cell = std::clamp(std::floor(u), 0.0, maxIndex);
    return {static_cast<std::size_t>(cell), u - cell};
  }

  double m_origin = 0.0;
  double m_spacing = 1.0;
  double m_inverseSpacing = 1.0;
  std::vector<HermiteNode> m_nodes;
};

}  // namespace tissuesim
