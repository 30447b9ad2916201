// SPDX-License-Identifier: Apache-2.0
#include "app/ReplayCommand.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "app/ImageSize.h"
#include "app/OutputFile.h"
#include "app/SceneSession.h"
#include "app/SceneSnapshot.h"
#include "app/SessionSteps.h"
#include "render/OffscreenImage.h"
#include "sim/SessionRecording.h"

namespace tissuesim::app {
namespace {

struct ReplayOptions {
  std::string recordingPath;
  std::string reportPath;
  std::string exportFolder;
  double exportEvery_s = 0.02;
  std::string snapshotPath;
  int frames = -1;  ///< the snapshot's frame; < 0: the end
  std::string size = "1280x800";
  bool isColourMap = false;
};

void replay(const ReplayOptions& options) {
  if (!options.reportPath.empty()) checkOutputWritable(options.reportPath, "--report");
  if (!options.snapshotPath.empty()) checkPngOutput(options.snapshotPath, "--snapshot");
  const ImageSize size = parseImageSize(options.size, "--size");
  if (options.frames < -1) throw CommandError("--frames must be 0 or more");
  if (options.snapshotPath.empty() && options.frames >= 0)
    throw CommandError("--frames is the --snapshot's frame: give --snapshot too");
  SessionRecording recording;
  try {
    recording = readRecording(options.recordingPath);
    checkFingerprints(recording, options.recordingPath);
  } catch (const RecordingError& error) {
    throw CommandError(error.what());
  }
  SceneSession session(recording.scenePath.string(), "",
                       recording.isLive ? InstrumentDriver::Live : InstrumentDriver::Script);
  session.printAssumptions();
  if (!recording.isLive && !recording.script.empty()) {
    try {
      session.useScript(InstrumentScript(recording.script));
    } catch (const std::invalid_argument& error) {
      throw CommandError(options.recordingPath + ": its script: " + error.what());
    }
  }
  const Simulation& simulation = session.simulation();
  long snapshotStep = recording.steps;  // after the last step
  if (options.frames >= 0) {
    snapshotStep = std::lround(options.frames / kSnapshotFrameRate_Hz / simulation.timeStep_s());
    if (snapshotStep > recording.steps) {
      char reason[160];
      std::snprintf(
          reason, sizeof reason,
          "--frames %d (%.2f s) lies past the recording's end (%.2f s, frame %ld)", options.frames,
          options.frames / kSnapshotFrameRate_Hz, recording.steps * simulation.timeStep_s(),
          static_cast<long>(recording.steps * simulation.timeStep_s() * kSnapshotFrameRate_Hz));
      throw CommandError(reason);
    }
  }
  std::optional<HeadlessDisplay> display;
  if (!options.snapshotPath.empty()) display.emplace();
  const auto snapshot = [&] {
    SnapshotSettings settings;
    settings.size = size;
    settings.isColourMap = options.isColourMap;
    const SceneSnapshot taken = takeSceneSnapshot(session, settings);  // 0 frames: as it is
    try {
      writePng(taken.image, options.snapshotPath);
    } catch (const std::runtime_error& error) {
      throw CommandError(error.what());
    }
    std::printf("wrote %s at step %ld (t = %.3f s)\n", options.snapshotPath.c_str(),
                simulation.steps(), simulation.time_s());
  };
  std::size_t next = 0;
  SessionOutputs outputs;
  outputs.sceneLabel = recording.scenePath.string();
  outputs.reportPath = options.reportPath;
  outputs.exportFolder = options.exportFolder;
  outputs.exportEvery_s = options.exportEvery_s;
  outputs.beforeStep = [&](long step) { applyRecordedChanges(recording, next, step, session); };
  outputs.afterStep = [&](long step) {
    if (!options.snapshotPath.empty() && step + 1 == snapshotStep) snapshot();
  };
  if (!options.snapshotPath.empty() && snapshotStep == 0) snapshot();
  runSessionSteps(session, recording.steps, outputs);
}

}  // namespace

void registerReplayCommand(CLI::App& app) {
  auto options = std::make_shared<ReplayOptions>();
  CLI::App* command = app.add_subcommand(
      "replay",
      "A recorded session (run --record, or the window's File > Save recording) stepped again "
      "headless, to the same bits: the same report as `run`, images of any frame.");
  command->add_option("--recording", options->recordingPath, "The recording")->required();
  command->add_option("--report", options->reportPath, "Write the JSON report here");
  command->add_option("--export", options->exportFolder,
                      "Write the replay for ParaView into this folder (as run --export)");
  command
      ->add_option("--export-every", options->exportEvery_s,
                   "Simulated seconds between exported frames")
      ->capture_default_str();
  command->add_option("--snapshot", options->snapshotPath, "Render a frame into this PNG");
  command->add_option("--frames", options->frames,
                      "The snapshot's frame, in 1/60 s of the replay (default: its end)");
  command->add_option("--size", options->size, "The snapshot's size, WIDTHxHEIGHT")
      ->capture_default_str();
  command->add_flag("--colour-map", options->isColourMap, "The snapshot with the stretch colours");
  command->callback([options] { replay(*options); });
}

}  // namespace tissuesim::app
