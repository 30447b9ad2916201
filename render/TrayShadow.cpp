// SPDX-License-Identifier: Apache-2.0
#include "render/TrayShadow.h"

#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkImageData.h>
#include <vtkPlaneSource.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkTexture.h>

namespace tissuesim {
namespace {

constexpr float kSteel[3] = {0.78f, 0.80f, 0.82f};
/// How dark a fully covered cell is (the rest of the light reaches it from the room).
constexpr float kShadowDepth = 0.55f;
constexpr int kBlurRadius = 2;

/// One box pass of radius kBlurRadius along rows or columns of an n x n grid, by a running sum
/// (the edges clamped).
void boxPass(const std::vector<float>& in, std::vector<float>& out, int n, bool isAlongRows) {
  const auto at = [&](int line, int k) {
    return static_cast<std::size_t>(isAlongRows ? line * n + k : k * n + line);
  };
  constexpr float kScale = 1.0f / (2 * kBlurRadius + 1);
  for (int line = 0; line < n; ++line) {
    float sum = 0.0f;
    for (int d = -kBlurRadius; d <= kBlurRadius; ++d) sum += in[at(line, std::clamp(d, 0, n - 1))];
    for (int k = 0; k < n; ++k) {
      out[at(line, k)] = sum * kScale;
      sum += in[at(line, std::min(k + kBlurRadius + 1, n - 1))] -
             in[at(line, std::max(k - kBlurRadius, 0))];
    }
  }
}

}  // namespace

TrayShadow::TrayShadow(double height_m, const Eigen::Vector2d& cornerXZ_m, double size_m)
    : m_height_m(height_m),
      m_corner_m(cornerXZ_m),
      m_cell_m(size_m / kCells),
      // The lamp above the organ, a little behind the eye's right shoulder: shadows fall back
      // and to the left, where the default camera sees them beside the organ.
      m_lampDirection(Eigen::Vector3d(-0.2, -1.0, -0.3).normalized()),
      m_coverage(kCells * kCells, 0.0f),
      m_shade(kCells * kCells, 0.0f),
      m_scratch(kCells * kCells, 0.0f),
      m_light(kCells * kCells, 1.0f),
      m_image(vtkSmartPointer<vtkImageData>::New()),
      m_actor(vtkSmartPointer<vtkActor>::New()) {
  const double centre = 0.5 * kCells;
  const double pool = 0.35 * kCells;  // the lamp's pool of light, in cells
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      const double r2 =
          ((i + 0.5 - centre) * (i + 0.5 - centre) + (j + 0.5 - centre) * (j + 0.5 - centre)) /
          (pool * pool);
      m_light[static_cast<std::size_t>(j * kCells + i)] =
          static_cast<float>(0.72 + 0.28 * std::exp(-r2));
    }
  }
  // One quad, its colours a texture of a texel a cell: texel (i, j) covers x from x0 + i cell,
  // z from z0 + j cell (the plane's texture coordinates run from its origin to its two points).
  auto plane = vtkSmartPointer<vtkPlaneSource>::New();
  plane->SetOrigin(cornerXZ_m.x(), height_m, cornerXZ_m.y());
  plane->SetPoint1(cornerXZ_m.x() + size_m, height_m, cornerXZ_m.y());
  plane->SetPoint2(cornerXZ_m.x(), height_m, cornerXZ_m.y() + size_m);
  m_image->SetDimensions(kCells, kCells, 1);
  m_image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(m_image);
  texture->InterpolateOn();
  texture->EdgeClampOn();
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(plane->GetOutputPort());
  m_actor->SetMapper(mapper);
  m_actor->SetTexture(texture);
  m_actor->GetProperty()->LightingOff();
  update(Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitY(), 0.0, 0.0);
}

TrayShadow::~TrayShadow() = default;

vtkActor* TrayShadow::actor() const { return m_actor; }

Eigen::Vector2d TrayShadow::project(const Eigen::Vector3d& point_m) const {
  const double t = (point_m.y() - m_height_m) / -m_lampDirection.y();
  const Eigen::Vector3d onTray = point_m + t * m_lampDirection;
  return {onTray.x(), onTray.z()};
}

void TrayShadow::splat(const Eigen::Vector3d& point_m, int radiusCells) {
  if (point_m.y() < m_height_m || !point_m.allFinite()) return;
  const Eigen::Vector2d cell = (project(point_m) - m_corner_m) / m_cell_m;
  const int ci = static_cast<int>(std::floor(cell.x()));
  const int cj = static_cast<int>(std::floor(cell.y()));
  for (int j = std::max(cj - radiusCells, 0); j <= std::min(cj + radiusCells, kCells - 1); ++j) {
    for (int i = std::max(ci - radiusCells, 0); i <= std::min(ci + radiusCells, kCells - 1); ++i)
      m_coverage[static_cast<std::size_t>(j) * kCells + static_cast<std::size_t>(i)] = 1.0f;
  }
}

void TrayShadow::blur() {
  boxPass(m_coverage, m_scratch, kCells, true);
  boxPass(m_scratch, m_shade, kCells, false);
  boxPass(m_shade, m_scratch, kCells, true);
  boxPass(m_scratch, m_shade, kCells, false);
}

void TrayShadow::update(const Eigen::Matrix3Xd& organPoints_m, const Eigen::Vector3d& tip_m,
                        const Eigen::Vector3d& direction, double shaftRadius_m,
                        double shaftLength_m) {
  std::fill(m_coverage.begin(), m_coverage.end(), 0.0f);
  for (Eigen::Index p = 0; p < organPoints_m.cols(); ++p) splat(organPoints_m.col(p), 1);
  if (shaftLength_m > 0.0 && direction.allFinite() && direction.norm() > 0.0) {
    // The shaft, sampled every half cell from its tip back along it.
    const Eigen::Vector3d back = -direction.normalized();
    const int radius = shaftRadius_m > 0.5 * m_cell_m ? 1 : 0;
    for (double s = 0.0; s <= shaftLength_m; s += 0.5 * m_cell_m) splat(tip_m + s * back, radius);
  }
  blur();
  auto* texels = static_cast<unsigned char*>(m_image->GetScalarPointer());
  for (std::size_t k = 0; k < m_shade.size(); ++k) {
    const float light = m_light[k] * (1.0f - kShadowDepth * m_shade[k]);
    for (std::size_t c = 0; c < 3; ++c) {
      texels[3 * k + c] =
          static_cast<unsigned char>(255.0f * std::clamp(kSteel[c] * light, 0.0f, 1.0f) + 0.5f);
    }
  }
  m_image->Modified();
}

}  // namespace tissuesim
