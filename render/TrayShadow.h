// SPDX-License-Identifier: Apache-2.0
#pragma once
// The steel tray under the organ, with the organ's and the tool's soft shadows baked into its
// texture each frame: a grid of cells on the tray's plane, each point of the organ's drawn
// surface and of the tool's shaft projected onto it along the lamp's direction and splatted, the
// coverage blurred (two box passes: a soft edge about two cells wide), and each texel darkened
// by it over a lamp's pool of light. The tray is one quad drawn unlit with that texture.
//
// Why not a shadow map: VTK's shadow-map passes draw the scene again from the light and filter
// every fragment, and under Mesa's llvmpipe each fragment is paid on the CPU; the tray lit by
// the renderer cost a fifth of a frame by itself. Drawn unlit with a texture, the tray and both
// shadows cost less than the lit tray alone did, and the shadows are soft for free. (A grid of
// vertex colours instead cost llvmpipe more in triangles than it saved in lighting.)
//
// Shapes: points 3 by #P (m); the grid is kCells by kCells cells over the tray's square.

#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

class vtkActor;
class vtkImageData;

namespace tissuesim {

class TrayShadow {
 public:
  static constexpr int kCells = 128;

  /// A horizontal tray (normal +y) at height_m, the square [x0, x0 + size] x [z0, z0 + size].
  TrayShadow(double height_m, const Eigen::Vector2d& cornerXZ_m, double size_m);
  ~TrayShadow();
  TrayShadow(const TrayShadow&) = delete;
  TrayShadow& operator=(const TrayShadow&) = delete;

  vtkActor* actor() const;
  double height_m() const { return m_height_m; }

  /// Shadows of the organ's surface points and of the tool's shaft (the segment from its tip
  /// `shaftLength_m` back along -direction, radius shaftRadius_m; none when shaftLength_m is 0).
  void update(const Eigen::Matrix3Xd& organPoints_m, const Eigen::Vector3d& tip_m,
              const Eigen::Vector3d& direction, double shaftRadius_m, double shaftLength_m);

  /// Coverage of cell (i, j) after the blur, in [0, 1] (tests).
  double shade(int i, int j) const {
    return m_shade[static_cast<std::size_t>(j) * kCells + static_cast<std::size_t>(i)];
  }
  /// Where a point falls on the tray along the lamp's direction (x, z in m).
  Eigen::Vector2d project(const Eigen::Vector3d& point_m) const;

 private:
  void splat(const Eigen::Vector3d& point_m, int radiusCells);
  void blur();

  double m_height_m;
  Eigen::Vector2d m_corner_m;
  double m_cell_m;
  Eigen::Vector3d m_lampDirection;  ///< unit, from the lamp down to the tray
  std::vector<float> m_coverage;    ///< kCells^2, splatted
  std::vector<float> m_shade;       ///< kCells^2, blurred
  std::vector<float> m_scratch;
  std::vector<float> m_light;             ///< kCells^2: the lamp's pool of light
  vtkSmartPointer<vtkImageData> m_image;  ///< the tray's colours, a texel a cell
  vtkSmartPointer<vtkActor> m_actor;
};

}  // namespace tissuesim
