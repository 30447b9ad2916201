#include "GuiCommand.h"

#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>

#include "AssetPaths.h"
#include "CommandError.h"
#include "gui/MainWindow.h"

namespace tissuesim::app {

int runGui(const std::string& scenePath, int argc, char** argv) {
  const char* display = std::getenv("DISPLAY");
  if (display == nullptr || *display == '\0') {
    // Qt would abort on a missing display; say what to do instead.
    throw CommandError(
        "the window needs an X display and DISPLAY is unset; for a headless check run "
        "'xvfb-run -a tissuesim', for images 'tissuesim snapshot --output FILE.png'");
  }
  // Mesa's software renderer takes every core by default; leave one to the physics thread, which
  // must keep its rate while frames are drawn (measured: Render/PhysicsRate in the benchmark).
  // A hardware driver ignores this.
  if (std::getenv("LP_NUM_THREADS") == nullptr) {
    const unsigned cores = std::thread::hardware_concurrency();
    ::setenv("LP_NUM_THREADS", std::to_string(cores > 1 ? cores - 1 : 1).c_str(), 0);
  }
  // Before QApplication: the OpenGL context VTK needs (VTK's Qt examples do the same).
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);
  MainWindow window(QString::fromStdString(scenePath));
  window.show();
  return QApplication::exec();
}

void registerGuiCommand(CLI::App& app, int argc, char** argv) {
  auto scenePath = std::make_shared<std::string>(bundledAsset("scenes/liver-poke.json").string());
  CLI::App* command = app.add_subcommand(
      "gui", "Open the interactive window (what `tissuesim` with no arguments does). Mouse: move "
             "to steer the tool, wheel to push it (Ctrl+wheel zooms), drag to turn the camera; "
             "keys: Space pause, R reset, G grasp, C colour map, W springs.");
  command->add_option("--scene", *scenePath, "Scene file (JSON)")->capture_default_str();
  command->callback([scenePath, argc, argv] {
    const int code = runGui(*scenePath, argc > 0 ? 1 : 0, argv);
    if (code != 0) std::exit(code);
  });
}

}  // namespace tissuesim::app
