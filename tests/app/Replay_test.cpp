// SPDX-License-Identifier: Apache-2.0
// `run --record` then `replay`, through the commands themselves: the replay's report is the
// run's, field for field, but for the wall-clock figures.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/ReplayCommand.h"
#include "app/RunCommand.h"
#include "sim/SceneFile.h"
#include "sim/SessionRecording.h"
#include "sim/Simulation.h"

namespace tissuesim::app {
namespace {

void runCommand(const std::vector<std::string>& arguments) {
  CLI::App app("tissuesim");
  app.require_subcommand(1);
  registerRunCommand(app);
  registerReplayCommand(app);
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
  app.parse(reversed);
}

nlohmann::json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(Replay, ARecordedRunReplaysToTheSameReport) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "tissuesim-replay-test";
  std::filesystem::create_directories(folder);
  const std::string recording = (folder / "run.jsonl").string();
  const std::string scene = std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json";
  // Far enough into the default poke to push the liver.
  runCommand({"run", "--scene", scene, "--duration", "0.8", "--record", recording, "--report",
              (folder / "run.json").string()});
  runCommand({"replay", "--recording", recording, "--report", (folder / "replay.json").string()});
  nlohmann::json run = readJson(folder / "run.json");
  nlohmann::json replay = readJson(folder / "replay.json");
  EXPECT_GT(run.at("max_tool_force_n").get<double>(), 0.1);
  // The session's assessment is in the report, and so in the comparison below.
  const nlohmann::json& assessment = run.at("assessment");
  EXPECT_EQ(assessment.at("peak_tool_force_n"), run.at("max_tool_force_n"));
  EXPECT_NEAR(assessment.at("duration_s").get<double>(), run.at("simulated_seconds").get<double>(),
              1e-9);
  EXPECT_GT(assessment.at("tool_path_length_mm").get<double>(), 10.0);
  EXPECT_GT(assessment.at("contact_time_s").get<double>(), 0.0);
  // The implicit step's work: the scene's one Newton iteration a step where the step does not
  // start in balance, at most eight extra ones more, each taking at least one CG product.
  const double newton = run.at("newton_iterations_per_step").get<double>();
  EXPECT_GT(newton, 0.5);
  EXPECT_LE(newton, 9.0);
  EXPECT_GE(run.at("cg_products_per_step").get<double>(), newton);
  for (const char* timing : {"physics_hz", "realtime_factor", "wall_seconds"}) {
    ASSERT_TRUE(run.contains(timing));
    run.erase(timing);
    replay.erase(timing);
  }
  EXPECT_EQ(run, replay);
  std::filesystem::remove_all(folder);
}

TEST(Replay, ABodyMadeAgainWhereTheToolAimsIsMadeAgainAtTheSameStep) {
  // A live session on the scene refined where its tool aims: the tool taken 4 cm along x (the
  // second poke site), the body made again there at step 600, then pressed there.
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "tissuesim-replay-refined-test";
  std::filesystem::create_directories(folder);
  const std::string scene = std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-refined.json";
  const SceneDescription description = loadSceneFile(scene);
  const Eigen::Vector3d direction = description.instrument->direction;
  const Eigen::Vector3d second(-0.04, 0.152, 0.045);
  SessionRecording recording;
  recording.scenePath = scene;
  recording.files = sceneFingerprints(scene);
  recording.isLive = true;
  RecordedEvent across;
  across.step = 1;
  across.pose = InstrumentPose{second, direction, false};
  RecordedEvent refined;
  refined.step = 600;
  refined.isRefinedTowardsTool = true;
  RecordedEvent pressed;
  pressed.step = 601;
  pressed.pose = InstrumentPose{second + 0.012 * direction, direction, false};
  recording.events = {across, refined, pressed};
  recording.steps = 2500;
  const std::string path = (folder / "refined.jsonl").string();
  writeRecording(path, recording);
  runCommand({"replay", "--recording", path, "--report", (folder / "first.json").string(),
              "--export", (folder / "export").string(), "--export-every", "0.5"});
  runCommand({"replay", "--recording", path, "--report", (folder / "second.json").string()});
  nlohmann::json first = readJson(folder / "first.json");
  nlohmann::json second_ = readJson(folder / "second.json");
  EXPECT_EQ(first.at("refined_towards_tool"), 1);
  EXPECT_EQ(first.at("instability_event_count"), 0);
  EXPECT_GT(first.at("max_tool_force_n").get<double>(), 0.05);
  // The mesh is the one the scene makes with its tool started at the second site.
  SceneDescription there = description;
  there.instrument->tipStart_m = second;
  const Simulation opened(there);
  EXPECT_EQ(first.at("nodes"), opened.springMesh().nodeCount());
  EXPECT_NE(first.at("nodes"), Simulation(description).springMesh().nodeCount());
  // The export took the new mesh up: a frame before it and after it.
  EXPECT_TRUE(std::filesystem::exists(folder / "export" / "tets_000000.vtu"));
  EXPECT_TRUE(std::filesystem::exists(folder / "export" / "tets_000005.vtu"));
  for (const char* timing : {"physics_hz", "realtime_factor", "wall_seconds", "export"}) {
    first.erase(timing);
    second_.erase(timing);
  }
  EXPECT_EQ(first, second_);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace tissuesim::app
