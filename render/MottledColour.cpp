// SPDX-License-Identifier: Apache-2.0
#include "render/MottledColour.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <vtkUnsignedCharArray.h>

namespace tissuesim {
namespace {

/// A value in [-1, 1] for a lattice point: an integer hash (no state, the same everywhere).
double latticeValue(std::int64_t i, std::int64_t j, std::int64_t k) {
  std::uint64_t h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
                    static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<std::uint64_t>(k) * 0x165667B19E3779F9ull;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53) * 2.0 - 1.0;
}

double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

}  // namespace

double smoothNoise(const Eigen::Vector3d& point_m, double cell_m) {
  const Eigen::Vector3d p = point_m / cell_m;
  const Eigen::Vector3d floor = p.array().floor();
  const Eigen::Vector3d t = p - floor;
  const auto i = static_cast<std::int64_t>(floor.x());
  const auto j = static_cast<std::int64_t>(floor.y());
  const auto k = static_cast<std::int64_t>(floor.z());
  const double sx = smoothstep(t.x()), sy = smoothstep(t.y()), sz = smoothstep(t.z());
  double value = 0.0;
  for (int dk = 0; dk < 2; ++dk) {
    for (int dj = 0; dj < 2; ++dj) {
      for (int di = 0; di < 2; ++di) {
        const double weight = (di ? sx : 1.0 - sx) * (dj ? sy : 1.0 - sy) * (dk ? sz : 1.0 - sz);
        value += weight * latticeValue(i + di, j + dj, k + dk);
      }
    }
  }
  return value;
}

vtkSmartPointer<vtkUnsignedCharArray> mottledColour(const Eigen::Matrix3Xd& rest_m,
                                                    const Eigen::Vector3d& baseColour) {
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetName("albedo");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(rest_m.cols());
  for (Eigen::Index v = 0; v < rest_m.cols(); ++v) {
    const Eigen::Vector3d p = rest_m.col(v);
    const double patch = 0.7 * smoothNoise(p, 0.015) + 0.3 * smoothNoise(p, 0.005);
    const double hue = smoothNoise(p + Eigen::Vector3d(0.37, 0.11, 0.53), 0.02);
    const double brightness = 1.0 + 0.15 * patch;
    // Redder where hue > 0, browner where < 0: green and blue follow red by different amounts.
    const Eigen::Vector3d colour =
        brightness * Eigen::Vector3d(baseColour.x(), baseColour.y() * (1.0 - 0.25 * hue),
                                     baseColour.z() * (1.0 - 0.35 * hue));
    unsigned char rgb[3];
    for (int c = 0; c < 3; ++c)
      rgb[c] = static_cast<unsigned char>(std::lround(255.0 * std::clamp(colour[c], 0.0, 1.0)));
    colours->SetTypedTuple(v, rgb);
  }
  return colours;
}

}  // namespace tissuesim
