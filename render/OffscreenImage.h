// SPDX-License-Identifier: Apache-2.0
#pragma once
// Renders a VTK renderer (a 3D scene or a chart's) into an image without showing a window, and
// reads and writes PNGs. Debian's VTK 9.1 renders through X only, so this needs a display:
// headless runs get one from Xvfb (app/HeadlessDisplay), rendered by Mesa's llvmpipe.

#include <filesystem>

#include <vtkSmartPointer.h>

class vtkImageData;
class vtkRenderWindow;
class vtkRenderer;

namespace tissuesim {

/// A hidden window kept for many frames (the frame benchmark): render() draws one frame.
class OffscreenWindow {
 public:
  OffscreenWindow(vtkRenderer* renderer, int width, int height);
  ~OffscreenWindow();
  OffscreenWindow(const OffscreenWindow&) = delete;
  OffscreenWindow& operator=(const OffscreenWindow&) = delete;
  void render();
  /// The last frame's pixels (RGB, 8 bits).
  vtkSmartPointer<vtkImageData> image();

 private:
  vtkRenderer* m_renderer;
  vtkSmartPointer<vtkRenderWindow> m_window;
};

/// One offscreen frame of `renderer` at width x height pixels (RGB, 8 bits).
vtkSmartPointer<vtkImageData> renderOffscreen(vtkRenderer* renderer, int width, int height);

/// @throws std::runtime_error naming the file when it cannot be written or read.
void writePng(vtkImageData* image, const std::filesystem::path& path);
vtkSmartPointer<vtkImageData> readPng(const std::filesystem::path& path);

}  // namespace tissuesim
