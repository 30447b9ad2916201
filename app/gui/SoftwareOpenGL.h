// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whether OpenGL here is a software rasteriser (Mesa's llvmpipe, softpipe, swrast: a VM or a
// headless server, as on this project's machines) rather than a GPU. The window turns off
// multisampled anti-aliasing on one: VTK's default of 4-8 samples makes llvmpipe draw every
// frame four times over (the window at 7-8 fps instead of 15-18 here, on one of two cores the
// physics would rather have), while on a GPU it costs next to nothing and stays on.

#include <QString>

namespace tissuesim::app {

/// The OpenGL renderer's name (GL_RENDERER) from a throwaway context; empty when none can be
/// made. Needs a QGuiApplication. Asked once, then remembered.
QString openGLRendererName();

/// True when openGLRendererName() names a software rasteriser.
bool isSoftwareOpenGL();

}  // namespace tissuesim::app
