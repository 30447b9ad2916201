// SPDX-License-Identifier: Apache-2.0
#include "app/RunCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/OutputFile.h"
#include "app/SceneSession.h"
#include "app/SessionSteps.h"
#include "material/TissueFile.h"
#include "mesh/TriangleSurface.h"
#include "render/TimeSeriesExport.h"
#include "sim/SceneFile.h"
#include "sim/SessionRecording.h"
#include "sim/Simulation.h"

namespace tissuesim::app {
namespace {

struct RunOptions {
  std::string scenePath;
  std::string scriptPath;
  double duration_s = 0.0;
  std::string reportPath;
  std::string exportFolder;
  double exportEvery_s = 0.02;
  std::string recordPath;
};

void runSession(const RunOptions& options) {
  if (!options.reportPath.empty()) checkOutputWritable(options.reportPath, "--report");
  if (!options.recordPath.empty()) checkOutputWritable(options.recordPath, "--record");
  SceneSession session(options.scenePath, options.scriptPath, InstrumentDriver::Script);
  session.printAssumptions();
  const InstrumentScript* script = session.script();
  const double duration = options.duration_s > 0.0 ? options.duration_s
                          : script                 ? script->duration_s()
                                                   : 1.0;
  if (!std::isfinite(duration) || duration > 3600.0)
    throw CommandError("--duration must be at most 3600 s");
  const long steps = std::lround(duration / session.simulation().timeStep_s());
  SessionOutputs outputs;
  outputs.sceneLabel = options.scenePath;
  outputs.reportPath = options.reportPath;
  outputs.exportFolder = options.exportFolder;
  outputs.exportEvery_s = options.exportEvery_s;
  runSessionSteps(session, steps, outputs);
  if (options.recordPath.empty()) return;
  // A scripted session is its scene and its script: the keyframes, to the bit.
  SessionRecording recording;
  recording.scenePath = options.scenePath;
  try {
    recording.files = sceneFingerprints(options.scenePath);
    if (script != nullptr) recording.script = script->keyframes();
    recording.steps = steps;
    writeRecording(options.recordPath, recording);
  } catch (const RecordingError& error) {
    throw CommandError(std::string("--record: ") + error.what());
  }
  std::printf("recorded %ld steps: %s\n", steps, options.recordPath.c_str());
}

}  // namespace

void registerRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand(
      "run",
      "A headless session of a scene: fixed-step physics with a scripted instrument (a "
      "default poke when no script is given), and a JSON report.");
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_option("--scene", options->scenePath, "Scene file (JSON)")->capture_default_str();
  command->add_option(
      "--script", options->scriptPath,
      "Instrument script: {\"poses\": [{\"time_s\", \"tip_m\", \"direction\"}...]}");
  command->add_option("--duration", options->duration_s,
                      "Simulated seconds (default: the script's length)");
  command->add_option("--report", options->reportPath, "Write the JSON report here");
  command->add_option("--record", options->recordPath,
                      "Write the session's recording here (tissuesim replay steps it again)");
  command->add_option("--export", options->exportFolder,
                      "Write the run for ParaView into this folder: the drawn surface (.vtp) and "
                      "the tet mesh (.vtu) with displacement and stretch, and series.pvd");
  command
      ->add_option("--export-every", options->exportEvery_s,
                   "Simulated seconds between exported frames")
      ->capture_default_str();
  command->callback([options] { runSession(*options); });
}

}  // namespace tissuesim::app
