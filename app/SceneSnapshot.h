// SPDX-License-Identifier: Apache-2.0
#pragma once
// A scene stepped for N frames and rendered offscreen: what `tissuesim snapshot` writes and what
// the image regression tests compare, through this one function.

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include "app/ImageSize.h"
#include "app/SceneSession.h"

namespace tissuesim::app {

/// Frames are at 60 Hz of simulated time: frame N shows the state after N / 60 s.
constexpr double kSnapshotFrameRate_Hz = 60.0;

struct SnapshotSettings {
  int frames = 0;
  ImageSize size{1280, 800};
  bool isColourMap = false;
  bool isWireframe = false;
};

struct SceneSnapshot {
  vtkSmartPointer<vtkImageData> image;
  double maxToolForce_N = 0.0;  ///< over the steps taken
  long badSteps = 0;            ///< refused or non-finite steps (see the simulation's events)
};

/// Steps `session` for settings.frames frames, then renders it. Needs an X display
/// (HeadlessDisplay).
SceneSnapshot takeSceneSnapshot(SceneSession& session, const SnapshotSettings& settings);

}  // namespace tissuesim::app
