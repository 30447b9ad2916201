// SPDX-License-Identifier: Apache-2.0
#include "app/gui/SoftwareOpenGL.h"

#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFunctions>

namespace tissuesim::app {

QString openGLRendererName() {
  static const QString name = [] {
    QOffscreenSurface surface;
    surface.create();
    QOpenGLContext context;
    if (!surface.isValid() || !context.create() || !context.makeCurrent(&surface)) return QString();
    const auto* renderer = context.functions()->glGetString(GL_RENDERER);
    QString result = renderer != nullptr
                         ? QString::fromLatin1(reinterpret_cast<const char*>(renderer))
                         : QString();
    context.doneCurrent();
    return result;
  }();
  return name;
}

bool isSoftwareOpenGL() {
  const QString name = openGLRendererName();
  for (const char* rasteriser : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer"}) {
    if (name.contains(QLatin1String(rasteriser), Qt::CaseInsensitive)) return true;
  }
  return false;
}

}  // namespace tissuesim::app
