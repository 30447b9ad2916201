// SPDX-License-Identifier: Apache-2.0
#include "app/gui/InstrumentInteractorStyle.h"

#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

namespace tissuesim::app {

vtkStandardNewMacro(InstrumentInteractorStyle)

    void InstrumentInteractorStyle::OnMouseMove() {
  if (GetState() == VTKIS_NONE && onHover) {
    const int* position = GetInteractor()->GetEventPosition();
    onHover(position[0], position[1]);
    return;
  }
  vtkInteractorStyleTrackballCamera::OnMouseMove();
}

void InstrumentInteractorStyle::OnMouseWheelForward() {
  if (GetInteractor()->GetControlKey() == 0 && onWheel) {
    onWheel(+1);
    return;
  }
  vtkInteractorStyleTrackballCamera::OnMouseWheelForward();
  if (onCameraMoved) onCameraMoved();
}

void InstrumentInteractorStyle::OnMouseWheelBackward() {
  if (GetInteractor()->GetControlKey() == 0 && onWheel) {
    onWheel(-1);
    return;
  }
  vtkInteractorStyleTrackballCamera::OnMouseWheelBackward();
  if (onCameraMoved) onCameraMoved();
}

void InstrumentInteractorStyle::OnLeftButtonUp() {
  const bool wasMoving = GetState() != VTKIS_NONE;
  vtkInteractorStyleTrackballCamera::OnLeftButtonUp();
  if (wasMoving && onCameraMoved) onCameraMoved();
}

void InstrumentInteractorStyle::OnMiddleButtonUp() {
  const bool wasMoving = GetState() != VTKIS_NONE;
  vtkInteractorStyleTrackballCamera::OnMiddleButtonUp();
  if (wasMoving && onCameraMoved) onCameraMoved();
}

void InstrumentInteractorStyle::OnRightButtonUp() {
  const bool wasMoving = GetState() != VTKIS_NONE;
  vtkInteractorStyleTrackballCamera::OnRightButtonUp();
  if (wasMoving && onCameraMoved) onCameraMoved();
}

}  // namespace tissuesim::app
