// SPDX-License-Identifier: Apache-2.0
#include "app/TradeCommand.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/SecondsSince.h"
#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/FemForceCache.h"
#include "app/HeadlessDisplay.h"
#include "app/IndentCommand.h"
#include "app/LoadedTissue.h"
#include "app/OrganPoke.h"
#include "app/OutputFile.h"
#include "app/SceneSession.h"
#include "app/trade/TradeGrid.h"
#include "app/trade/TradeOutput.h"
#include "fem/FemModel.h"
#include "mesh/TetMeshFile.h"
#include "sim/SceneFile.h"

namespace tissuesim::app {
namespace {

struct TradeOptions {
  bool isQuick = false;
  std::string outputFolder = ".";
  std::string scenePath;
  std::vector<int> springs;
  std::vector<double> depths_mm{1.0, 2.0, 3.0, 4.0};
  std::string organReferencePath;
  std::string femMeshPath;
  /// The organ's meshes on which the FEM is a row of the liver poke; "none": no such rows.
  std::vector<std::string> organMeshPaths;
  /// The scene of the FEM at its own rate, the contact at 1 kHz, that is a row; "none": no such
  /// row.
  std::string hapticRateScenePath;
};

/// One line a task on stderr: a bar of the share done, the count, what runs now.
class ProgressBar {
 public:
  explicit ProgressBar(int total) : m_total(total) {}
  void start(const std::string& what) {
    constexpr int kWidth = 24;
    const int filled = m_total > 0 ? kWidth * m_done / m_total : kWidth;
    std::fprintf(stderr, "trade [%s%s] %2d/%d  %s\n", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), m_done + 1, m_total, what.c_str());
    ++m_done;
  }

 private:
  int m_total;
  int m_done = 0;
};

TradeSettings settingsFor(const TradeOptions& options) {
  TradeSettings settings;
  settings.isQuick = options.isQuick;
  settings.resolutions = options.isQuick ? std::vector<int>{1000, 5300, 20000}
                                         : std::vector<int>{1000, 5300, 20000, 100000};
  if (!options.springs.empty()) settings.resolutions = options.springs;
  for (const int count : settings.resolutions) {
    if (count < 200 || count > 200000)
      throw CommandError("--springs " + std::to_string(count) +
                         " is out of range; expected 200 to 200000");
  }
  settings.depths_m = indentationDepthsFromMm(options.depths_mm);
  settings.referenceRefinement = options.isQuick ? 1 : 3;
  if (!options.isQuick) settings.femRows = {1, 2};
  // The tets' FEM on the lattices: its static solves take minutes past 5,300 springs' lattice
  // and hours at 100,000.
  const int largestTets = options.isQuick ? 5300 : 20000;
  for (const int count : settings.resolutions) {
    if (count <= largestTets) settings.tetResolutions.push_back(count);
  }
  settings.tensileResolution = options.isQuick ? 1 : 2;
  settings.tensilePoints = options.isQuick ? 10 : 25;
  settings.costRounds = options.isQuick ? 2 : 3;
  settings.pokeSeconds = options.isQuick ? 1.0 : 0.0;  // quick: the press alone
  return settings;
}

/// The liver poke's FEM reference for `bundled` from the kept forces at `options`'
/// organReferencePath (organ-poke --fem-cache); its depths into the map's settings. Without one
/// (another scene or tissue, no such file) the map has no liver poke, and its note says why.
void loadOrganReference(const TradeOptions& options, const SceneDescription& bundled,
                        const LoadedTissue& tissue, TradeMap& map) {
  if (options.isQuick) {
    // The liver poke would take the quick map past its two minutes.
    map.organNote = "the full map measures it (without --quick)";
    return;
  }
  std::vector<double> depths_m;
  for (const double depth : kOrganPokeDepths_mm) depths_m.push_back(depth / 1000.0);
  try {
    const SceneDescription weightless = weightlessPokeScene(bundled);
    const std::uint64_t key =
        femReferenceKey(weightless, options.femMeshPath, organPokeSetup(weightless, depths_m),
                        defaultFemBulkModulus(tissue.energy));
    std::string why;
    const std::optional<std::vector<double>> forces =
        readFemForceCache(options.organReferencePath, key, kOrganPokeDepths_mm, why);
    if (!forces) {
      map.organNote = options.organReferencePath + " has no reference for this scene: " + why;
      return;
    }
    map.organReference_N = *forces;
    map.settings.organDepths_m = depths_m;
    for (const std::string& path : options.organMeshPaths) {
      if (path == "none") continue;
      map.settings.organMeshes.push_back(
          OrganMesh{path, std::filesystem::path(path).stem().string()});
    }
  } catch (const CommandError& error) {
    map.organNote = error.what();
  }
}

/// An FEM row: a coarser reference, its error against the finest and its time per load step.
void measureFemRow(const LoadedTissue& tissue, const TradeMap& map, const TradeRow& row,
                   TradeMeasurement& m) {
  const IndentationCurve fem = measureReference(tissue, map.settings, row.femRefinement);
  m.cost.nodes = fem.nodes;
  m.staticForce_N = fem.force_N;
  const double loadSteps =
      std::ceil(map.settings.depths_m.back() / IndentationSetup{}.depthStep_m - 1e-9);
  m.cost.stepMedian_ms = 1e3 * fem.seconds / std::max(1.0, loadSteps);
  setSurfaceGap(fem.surfaceDisplacement_m, map.reference.surfaceDisplacement_m, m);
}

void runTrade(const TradeOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  TradeMap map;
  map.settings = settingsFor(options);
  const std::filesystem::path folder(options.outputFolder);
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) {
    throw CommandError("--output " + options.outputFolder + ": cannot create the folder (" +
                       error.message() + ")");
  }
  const std::string csvPath = (folder / "tradeoff.csv").string();
  const std::string mdPath = (folder / "tradeoff.md").string();
  const std::string pngPath = (folder / "tradeoff.png").string();
  const std::string liverPngPath = (folder / "tradeoff-liver.png").string();
  for (const std::string& path : {csvPath, mdPath, pngPath, liverPngPath})
    checkOutputWritable(path, "--output");

  // The organ's meshes are read now: a bad one would otherwise stop the map minutes in.
  std::vector<std::pair<std::string, std::string>> organMeshes;  // option, path
  for (const std::string& path : options.organMeshPaths)
    organMeshes.emplace_back("--organ-meshes", path);
  for (const auto& [option, path] : organMeshes) {
    if (path == "none") continue;
    if (!std::filesystem::is_regular_file(path) || !isTetMeshFile(path)) {
      throw CommandError(option + " " + path +
                         ": no such tet mesh file (expected Gmsh .msh or TetGen .node/.ele)");
    }
    try {
      readTetMesh(path);
    } catch (const MeshFileError& failure) {
      throw CommandError(option + ": " + std::string(failure.what()));
    }
  }
  std::optional<SceneDescription> hapticRate;
  if (options.hapticRateScenePath != "none") {
    hapticRate = readScene(options.hapticRateScenePath);
    if (hapticRate->model != "fem-haptic-rate") {
      throw CommandError("--haptic-rate-scene " + options.hapticRateScenePath +
                         ": its effects.model is " + hapticRate->model +
                         "; expected fem-haptic-rate");
    }
  }
  const SceneDescription bundled = readScene(options.scenePath);
  const LoadedTissue tissue(bundled.tissue.string());
  map.settings.tetBulkModulus_Pa = defaultFemBulkModulus(tissue.energy);
  map.tissueName = tissue.parameters.name;
  map.sceneName = bundled.name;
  // The liver poke's reference first: it adds the rows on the organ's meshes.
  map.settings.organCacheFolder = options.outputFolder;
  loadOrganReference(options, bundled, tissue, map);
  // The FEM scene's row, with a liver poke to measure it on.
  if (!map.settings.organDepths_m.empty()) map.settings.hapticRateScene = hapticRate;
  map.rows = tradeRows(bundled, map.settings);
  if (!map.organNote.empty())
    std::fprintf(stderr, "trade: no liver poke: %s\n", map.organNote.c_str());
  TradeErrors errors(tissue, bundled, map.settings);

  // The rows timed on the bundled poke: all but the FEM's (the block's reference, and the FEM on
  // the organ's meshes, timed on the liver poke).
  const auto isTimedOnThePoke = [](const TradeRow& row) {
    return row.femRefinement == 0 && !row.isOnOrganMesh();
  };
  int springRows = 0;
  for (const TradeRow& row : map.rows) springRows += isTimedOnThePoke(row) ? 1 : 0;
  const int rounds = map.settings.costRounds;
  ProgressBar progress(1 + static_cast<int>(map.rows.size()) + rounds * springRows);
  progress.start("the FEM reference (refinement " +
                 std::to_string(map.settings.referenceRefinement) + ")");
  map.reference = measureReference(tissue, map.settings, map.settings.referenceRefinement);
  if (map.reference.unconvergedPoints > 0) {
    throw CommandError("the FEM reference did not converge at " +
                       std::to_string(map.reference.unconvergedPoints) +
                       " load steps; choose shallower --depths-mm");
  }
  // Accuracy first, a row at a time; then the cost, the rows interleaved round by round.
  map.measurements.resize(map.rows.size());
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    const TradeRow& row = map.rows[r];
    TradeMeasurement& m = map.measurements[r];
    progress.start("accuracy: " + row.name);
    if (row.femRefinement > 0) {
      measureFemRow(tissue, map, row, m);
      map.cellEdges_m.push_back(0.0);
      continue;
    }
    if (row.isOnOrganMesh()) {
      map.cellEdges_m.push_back(0.0);
      try {
        errors.measureOrgan(row, m);
      } catch (const CommandError& failure) {
        m.organFailure = failure.what();
      } catch (const SceneFileError& failure) {
        m.organFailure = failure.what();
      }
      continue;
    }
    try {
      errors.measure(row, map.reference, m);
    } catch (const std::invalid_argument& failure) {
      m.failure = std::string("block: ") + failure.what();
    }
    map.cellEdges_m.push_back(errors.cellEdge(row.targetSprings));
    // The liver poke for the spring rows (the tets' FEM on the lattice takes minutes a row
    // there).
    if (map.settings.organDepths_m.empty() || row.model != "springs") continue;
    try {
      errors.measureOrgan(row, m);
    } catch (const CommandError& failure) {
      m.organFailure = failure.what();
    }
  }
  std::vector<std::vector<TradeCost>> costs(map.rows.size());
  for (int round = 1; round <= rounds; ++round) {
    for (std::size_t r = 0; r < map.rows.size(); ++r) {
      if (!isTimedOnThePoke(map.rows[r])) continue;
      progress.start("cost, round " + std::to_string(round) + " of " + std::to_string(rounds) +
                     ": " + map.rows[r].name);
      costs[r].push_back(measureLiverCost(bundled, map.rows[r], map.settings.pokeSeconds));
    }
  }
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    if (costs[r].empty()) continue;
    TradeMeasurement& m = map.measurements[r];
    m.cost = medianOfRounds(costs[r]);
    if (m.failure.empty()) m.failure = m.cost.failure;
  }
  map.wall_s = secondsSince(started);
  writeTextFile(csvPath, "--output", tradeCsv(map));
  writeTextFile(mdPath, "--output", tradeMarkdown(map));
  const HeadlessDisplay display;  // one for both plots
  writeTradePlot(map, pngPath);
  std::printf("%s", tradeMarkdown(map).c_str());
  if (!map.organReference_N.empty()) {
    writeLiverTradePlot(map, liverPngPath);
    std::printf("\nwrote %s, %s, %s and %s\n", csvPath.c_str(), mdPath.c_str(), pngPath.c_str(),
                liverPngPath.c_str());
  } else {
    std::printf("\nwrote %s, %s and %s\n", csvPath.c_str(), mdPath.c_str(), pngPath.c_str());
  }
}

}  // namespace

void registerTradeCommand(CLI::App& app) {
  auto options = std::make_shared<TradeOptions>();
  CLI::App* command = app.add_subcommand(
      "trade",
      "The speed/accuracy map: the bundled scene at several resolutions, spring laws, volume "
      "terms and integrators, and the tets' FEM on the same lattices (effects.model fem), each "
      "timed on the liver and measured against the FEM reference "
      "on the indentation test and, the spring rows, on the liver poke (organ-poke); and the "
      "FEM on meshes of the organ (per tet, per face, the reference's quadratic tets solved "
      "statically, and at their own rate with the contact at 1 kHz), measured on the liver poke "
      "alone. Writes tradeoff.csv, "
      "tradeoff.md, tradeoff.png (the block's error against time per step, the Pareto front, "
      "the 1 ms budget) and, with the liver poke, tradeoff-liver.png (the same for the liver "
      "poke); a progress bar on stderr.");
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_flag("--quick", options->isQuick,
                    "1,000 to 20,000 springs (the tets' FEM to 5,300), a coarser FEM "
                    "reference, a smaller tensile specimen, two rounds of timings over the "
                    "poke's press alone, no liver poke (about two minutes); else up to 100,000 "
                    "springs (the tets' FEM to 20,000), three rounds over the whole poke, the "
                    "liver poke (about half an hour)");
  command
      ->add_option("--output", options->outputFolder,
                   "Folder for the files: tradeoff.csv, .md, .png and, with the liver poke, "
                   "tradeoff-liver.png")
      ->capture_default_str();
  command->add_option("--scene", options->scenePath, "The scene whose knobs are varied")
      ->capture_default_str();
  command
      ->add_option("--springs", options->springs,
                   "Resolutions on the liver, in springs (default: 1000,5300,20000[,100000])")
      ->delimiter(',');
  command
      ->add_option("--depths-mm", options->depths_mm,
                   "Indentation depths, increasing, at most 4.5 mm (the continuum locks deeper "
                   "under the 2.5 mm probe)")
      ->delimiter(',')
      ->capture_default_str();
  options->organReferencePath = bundledAsset("meshes/liver-fem-poke.csv").string();
  command
      ->add_option("--organ-reference", options->organReferencePath,
                   "The liver poke's FEM forces kept by organ-poke --fem-cache for the scene; "
                   "without them for this scene, the map has no liver poke")
      ->capture_default_str();
  options->femMeshPath = bundledAsset("meshes/liver-fem.msh").string();
  command
      ->add_option("--fem-mesh", options->femMeshPath,
                   "The conformal tet mesh that reference was solved on")
      ->capture_default_str();
  for (const char* mesh : {"liver-graded-5mm", "liver-graded-2p5mm", "liver-graded-1p25mm"})
    options->organMeshPaths.push_back(
        bundledAsset(std::string("meshes/") + mesh + ".msh").string());
  command
      ->add_option("--organ-meshes", options->organMeshPaths,
                   "Tet meshes of the organ (metres, conformal with its drawn surface) on which "
                   "the FEM, per tet and per face, and the reference's quadratic tets (static; "
                   "their forces read from MESH-poke.csv beside the mesh or in --output, else "
                   "solved, minutes, and kept in --output) are rows measured on the liver poke "
                   "alone; 'none': no such rows (default: the bundled liver's meshes graded to 5, "
                   "2.5 and 1.25 mm at the probe)")
      ->delimiter(',');
  options->hapticRateScenePath = bundledAsset("scenes/liver-fem-refined.json").string();
  command
      ->add_option("--haptic-rate-scene", options->hapticRateScenePath,
                   "The scene whose model is the reference's quadratic tets at their own rate "
                   "with the probe's contact at 1 kHz (effects.model fem-haptic-rate): a row "
                   "measured on the liver poke through its own steps and on the block through "
                   "the same scheme; 'none': no such row")
      ->capture_default_str();
  command->callback([options] { runTrade(*options); });
}

}  // namespace tissuesim::app
