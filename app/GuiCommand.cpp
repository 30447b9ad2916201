// SPDX-License-Identifier: Apache-2.0
#include "app/GuiCommand.h"

#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include <QVTKOpenGLNativeWidget.h>
#include <QApplication>
#include <QSurfaceFormat>

#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "app/gui/MainWindow.h"

namespace tissuesim::app {

int runGui(const std::string& scenePath, const std::string& recordingPath, int argc, char** argv) {
  const char* display = std::getenv("DISPLAY");
  if (display == nullptr || *display == '\0') {
    // Qt would abort on a missing display; say what to do instead.
    throw CommandError(
        "the window needs an X display and DISPLAY is unset; for a headless check run "
        "'xvfb-run -a tissuesim', for images 'tissuesim snapshot --output FILE.png'");
  }
  leaveACoreForPhysics();  // measured: Render/PhysicsRate in the benchmark
  // Before QApplication: the OpenGL context VTK needs (VTK's Qt examples do the same).
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  MainWindow window(QString::fromStdString(scenePath));
  window.show();
  // A refused recording has shown its error dialog; the window stays on the scene.
  if (!recordingPath.empty()) window.openRecording(QString::fromStdString(recordingPath));
  return QApplication::exec();
}

void registerGuiCommand(CLI::App& app, int argc, char** argv) {
  auto scenePath = std::make_shared<std::string>(bundledAsset("scenes/liver-poke.json").string());
  auto recordingPath = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "gui",
      "Open the interactive window (what `tissuesim` with no arguments does). Mouse: move "
      "to steer the tool, wheel to push it (Ctrl+wheel zooms), drag to turn the camera; "
      "keys: Space pause, R reset, G grasp, C colour map, W springs; [ and ] move a playback "
      "5 s.");
  command->add_option("--scene", *scenePath, "Scene file (JSON)")->capture_default_str();
  command->add_option("--recording", *recordingPath,
                      "Play this recording in the window (its own scene)");
  command->callback([scenePath, recordingPath, argc, argv] {
    const int code = runGui(*scenePath, *recordingPath, argc > 0 ? 1 : 0, argv);
    if (code != 0) std::exit(code);
  });
}

}  // namespace tissuesim::app
