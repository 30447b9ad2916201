// SPDX-License-Identifier: Apache-2.0
#pragma once
// Mouse handling of the trainee's view: VTK's trackball camera (left drag rotates, middle drag
// pans, right drag or Ctrl+wheel zooms), except that moving the mouse with no button pressed
// moves the instrument's tip under the cursor (at its current depth), and the wheel pushes the
// tool along its shaft (depth). The window decides what those mean through its callbacks; the
// end of each camera move is one of them, since the tip follows the cursor at its depth and a
// turned camera puts another point of the scene under the cursor.

#include <functional>

#include <vtkInteractorStyleTrackballCamera.h>

namespace tissuesim::app {

class InstrumentInteractorStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static InstrumentInteractorStyle* New();
  vtkTypeMacro(InstrumentInteractorStyle, vtkInteractorStyleTrackballCamera)

      /// Display coordinates (pixels, VTK's origin bottom-left) of a hover.
      std::function<void(int x, int y)> onHover;
  /// +1 per wheel notch forward (deeper), -1 backward.
  std::function<void(int notches)> onWheel;
  /// After a camera move ends (a rotate, pan, spin or zoom drag released, a Ctrl+wheel zoom).
  std::function<void()> onCameraMoved;

  void OnMouseMove() override;
  void OnMouseWheelForward() override;
  void OnMouseWheelBackward() override;
  void OnLeftButtonUp() override;
  void OnMiddleButtonUp() override;
  void OnRightButtonUp() override;

 protected:
  InstrumentInteractorStyle() = default;
};

}  // namespace tissuesim::app
