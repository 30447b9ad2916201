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

}  // namespace
}  // namespace tissuesim::app
