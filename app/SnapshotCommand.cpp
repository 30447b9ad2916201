// SPDX-License-Identifier: Apache-2.0
#include "app/SnapshotCommand.h"

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "app/ImageSize.h"
#include "app/SceneSnapshot.h"
#include "render/OffscreenImage.h"

namespace tissuesim::app {
namespace {

struct SnapshotOptions {
  std::string scenePath;
  std::string scriptPath;
  int frames = 0;
  std::string outputPath;
  std::string size = "1280x800";
  bool isColourMap = false;
  bool isWireframe = false;
};

void takeSnapshot(const SnapshotOptions& options) {
  checkPngOutput(options.outputPath, "--output");
  if (options.frames < 0 || options.frames > 100000) {
    throw CommandError("--frames " + std::to_string(options.frames) + ": expected 0 to 100000");
  }
  const SnapshotSettings settings{options.frames, parseImageSize(options.size, "--size"),
                                  options.isColourMap, options.isWireframe};
  // Everything that can be refused is checked before a display is started.
  SceneSession session(options.scenePath, options.scriptPath, InstrumentDriver::Script);
  session.printAssumptions();
  const HeadlessDisplay display;
  const SceneSnapshot snapshot = takeSceneSnapshot(session, settings);
  try {
    writePng(snapshot.image, options.outputPath);
  } catch (const std::runtime_error& error) {
    throw CommandError(error.what());
  }
  const Simulation& simulation = session.simulation();
  std::printf(
      "%s: %d frames (%ld steps, t = %.3f s), max tool force %.3f N, %zu instability events; wrote "
      "%s (%dx%d)\n",
      session.scene().name.c_str(), options.frames, simulation.steps(), simulation.time_s(),
      snapshot.maxToolForce_N, simulation.eventCount(), options.outputPath.c_str(),
      settings.size.width, settings.size.height);
}

}  // namespace

void registerSnapshotCommand(CLI::App& app) {
  auto options = std::make_shared<SnapshotOptions>();
  CLI::App* command = app.add_subcommand(
      "snapshot",
      "Step a scene headless and render its state offscreen to a PNG (a private Xvfb is started "
      "when there is no DISPLAY). Frame N is the state after N/60 s of simulated time; the same "
      "inputs give the same image.");
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_option("--scene", options->scenePath, "Scene file (JSON)")->capture_default_str();
  command->add_option("--script", options->scriptPath,
                      "Instrument script (default: the scene's poke)");
  command->add_option("--frames", options->frames, "Frames of 1/60 s to simulate before the image")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "PNG to write")->required();
  command->add_option("--size", options->size, "Image size WIDTHxHEIGHT in pixels")
      ->capture_default_str();
  command->add_flag("--colour-map,--color-map", options->isColourMap,
                    "Colour the surface by spring stretch");
  command->add_flag("--wireframe", options->isWireframe, "Show the springs");
  command->callback([options] { takeSnapshot(*options); });
}

}  // namespace tissuesim::app
