// SPDX-License-Identifier: Apache-2.0
// The liver poke's kept FEM reference (assets/meshes/liver-fem-poke.csv, which `trade` reads and
// `measure` passes to organ-poke) belongs to the bundled scene as it is: a change to its tissue,
// its instrument, its fixed region, the conformal mesh or the reference's solver changes the key,
// and this test fails until the reference is solved again (assets/meshes/README.md). And the
// map's liver poke (trade) is organ-poke's simulator side.

#include "app/OrganPoke.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/IndentationHapticRate.h"
#include "app/CommandError.h"
#include "app/FemForceCache.h"
#include "app/LoadedTissue.h"
#include "app/SceneSession.h"
#include "app/trade/TradeGrid.h"
#include "fem/FemModel.h"
#include "mesh/TetMeshFile.h"

namespace tissuesim::app {
namespace {

const std::string kAssets = TISSUESIM_ASSET_DIR;

/// The map's liver poke of the bundled scene at 1,000 springs, to 1 and 3 mm.
struct BundledMapPoke {
  SceneDescription bundled = readScene(kAssets + "/scenes/liver-poke.json");
  LoadedTissue tissue{bundled.tissue.string()};
  TradeSettings settings = [] {
    TradeSettings made;
    made.resolutions = {1000};
    made.organDepths_m = {0.001, 0.003};
    return made;
  }();
};

/// The liver poke's depths (organ-poke's), in metres.
std::vector<double> organPokeDepths_m() {
  std::vector<double> depths_m;
  for (const double depth : kOrganPokeDepths_mm) depths_m.push_back(depth / 1000.0);
  return depths_m;
}

/// The liver poke's forces kept in assets/meshes/`kept` for the reference on assets/meshes/`mesh`,
/// when they are `scene`'s reference.
std::optional<std::vector<double>> keptPokeForces(const SceneDescription& scene,
                                                  const std::string& mesh, const std::string& kept,
                                                  std::string& why) {
  const LoadedTissue tissue(scene.tissue.string());
  return readFemForceCache(kAssets + "/meshes/" + kept,
                           femReferenceKey(scene, kAssets + "/meshes/" + mesh,
                                           organPokeSetup(scene, organPokeDepths_m()),
                                           defaultFemBulkModulus(tissue.energy)),
                           kOrganPokeDepths_mm, why);
}

TEST(OrganPoke, TheBundledLiverPokesKeptForcesAreTheBundledScenes) {
  // The reference on its mesh, and the reference's element on the map's graded meshes (`trade`
  // reads these; the 5 mm mesh's solves do not all converge, so it keeps none).
  const SceneDescription scene =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  for (const auto& [mesh, kept] :
       {std::pair<std::string, std::string>{"liver-fem.msh", "liver-fem-poke.csv"},
        {"liver-graded-2p5mm.msh", "liver-graded-2p5mm-poke.csv"},
        {"liver-graded-1p25mm.msh", "liver-graded-1p25mm-poke.csv"}}) {
    std::string why;
    const auto forces = keptPokeForces(scene, mesh, kept, why);
    ASSERT_TRUE(forces.has_value()) << kept << ": " << why;
    // The continuum stiffens with depth under the probe.
    for (std::size_t d = 1; d < forces->size(); ++d)
      EXPECT_GT((*forces)[d], (*forces)[d - 1]) << kept;
  }
}

/// The second site, 4 cm along x from the bundled poke (`measure` passes `--probe-at
/// -0.04,0.152,0.045`), and its reference graded there, kept to 5 mm.
const Eigen::Vector3d kSecondSite_m(-0.04, 0.152, 0.045);
const std::vector<double> kSecondSiteDepths_mm{1.0, 2.0, 3.0, 4.0, 5.0};
const std::vector<double> kSecondSiteDepths_m{0.001, 0.002, 0.003, 0.004, 0.005};

/// The second site's kept forces, when they are `scene`'s reference there.
std::optional<std::vector<double>> secondSiteKeptForces(const SceneDescription& scene,
                                                        std::string& why) {
  const LoadedTissue tissue(scene.tissue.string());
  const std::string mesh = kAssets + "/meshes/liver-fem-site-b.msh";
  return readFemForceCache(kAssets + "/meshes/liver-fem-site-b-poke.csv",
                           femReferenceKey(scene, mesh, organPokeSetup(scene, kSecondSiteDepths_m),
                                           defaultFemBulkModulus(tissue.energy)),
                           kSecondSiteDepths_mm, why);
}

TEST(OrganPoke, TheSecondSitesKeptForcesAreTheBundledScenesProbeMovedThere) {
  // Its key is the bundled scene's with the probe moved there, not the bundled poke's.
  const SceneDescription bundled =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  SceneDescription moved = bundled;
  moved.instrument->tipStart_m = kSecondSite_m;
  std::string why;
  const auto forces = secondSiteKeptForces(moved, why);
  ASSERT_TRUE(forces.has_value()) << why;
  for (std::size_t d = 1; d < forces->size(); ++d) EXPECT_GT((*forces)[d], (*forces)[d - 1]);
  EXPECT_FALSE(secondSiteKeptForces(bundled, why).has_value());
}

/// A poke through a scene's own steps with no event, its force at each depth from `first` on
/// within `tolerance` of the reference's (as a ratio).
void expectWithinAtEachDepth(const SimulatorPoke& poke, const std::vector<double>& reference,
                             const std::vector<double>& depths_mm, double tolerance,
                             std::size_t first = 0) {
  EXPECT_EQ(poke.events, 0);
  for (std::size_t d = first; d < depths_mm.size(); ++d) {
    EXPECT_NEAR(poke.force_N[d] / reference[d], 1.0, tolerance) << depths_mm[d] << " mm";
  }
}

TEST(OrganPoke, TheRefinedFemSceneIsWithinTenPerCentOfTheReferenceAtTheBundledEntry) {
  // The coarse body refined where the tool aims, its boundary bent onto the drawn surface: the
  // liver poke through the scene's own steps, against the bundled poke's kept reference, at every
  // depth to 10 mm. Left with the coarse mesh's chords, inside the drawn surface, the same body
  // reads soft (docs/performance-details.md, "The boundary bent onto the drawn surface").
  const SceneDescription scene =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-fem-refined.json"));
  std::string why;
  const auto reference = keptPokeForces(scene, "liver-fem.msh", "liver-fem-poke.csv", why);
  const std::vector<double> depths_m = organPokeDepths_m();
  ASSERT_TRUE(reference.has_value()) << why;
  expectWithinAtEachDepth(pokeSimulator(scene, depths_m, 0.002), *reference, kOrganPokeDepths_mm,
                          0.10);
}

TEST(OrganPoke, TheFemSceneRefinedAtTheSecondSiteIsWithinTenPerCentOfItsReference) {
  // The refined scene's tool started over the second site, its body refined there to 3 mm (the
  // scene's 4 mm is not within 10 % at 1 mm there: docs/performance-details.md, "The boundary bent
  // onto the drawn surface"): the liver poke there through the scene's own steps, against the
  // reference kept for that site.
  SceneDescription moved =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-fem-refined.json"));
  moved.instrument->tipStart_m = kSecondSite_m;
  ASSERT_TRUE(moved.tetMesh->refinement.has_value());
  moved.tetMesh->refinement->finest_m = 0.003;
  std::string why;
  const auto reference = secondSiteKeptForces(moved, why);
  ASSERT_TRUE(reference.has_value()) << why;
  expectWithinAtEachDepth(pokeSimulator(moved, kSecondSiteDepths_m, 0.002), *reference,
                          kSecondSiteDepths_mm, 0.10);
  // The same body as the file has it, 24 mm tets there: far too stiff.
  SceneDescription coarse = moved;
  coarse.tetMesh->refinement.reset();
  const SimulatorPoke unrefined = pokeSimulator(coarse, kSecondSiteDepths_m, 0.002);
  EXPECT_GT(unrefined.force_N[1] / (*reference)[1], 1.3);
}

/// The bundled poke as the default scene holds the liver (its weight, its tray), kept to 5 mm in
/// assets/meshes/liver-fem-weighted-poke.csv, when those are `scene`'s reference.
const std::vector<double> kWeightedDepths_mm{1.0, 2.0, 3.0, 4.0, 5.0};
const std::vector<double> kWeightedDepths_m{0.001, 0.002, 0.003, 0.004, 0.005};

std::optional<std::vector<double>> weightedKeptForces(const SceneDescription& scene,
                                                      std::string& why) {
  const LoadedTissue tissue(scene.tissue.string());
  return readFemForceCache(
      kAssets + "/meshes/liver-fem-weighted-poke.csv",
      femReferenceKey(scene, kAssets + "/meshes/liver-fem.msh",
                      organPokeSetup(scene, kWeightedDepths_m, tissue.parameters.density_kg_m3),
                      defaultFemBulkModulus(tissue.energy)),
      kWeightedDepths_mm, why);
}

/// `scene` given the default scene's gravity and tray.
SceneDescription heldAsTheDefaultScene(SceneDescription scene) {
  const SceneDescription bundled = readScene(kAssets + "/scenes/liver-poke.json");
  scene.gravity_m_s2 = bundled.gravity_m_s2;
  scene.tray = bundled.tray;
  return weightedPokeScene(scene);
}

TEST(OrganPoke, TheWeightedPokesKeptForcesAreTheDefaultScenes) {
  // Under its weight the liver hangs from its hold and its surface is stretched taut: the same
  // poke reads several times the weightless liver's force at every depth.
  const SceneDescription scene = weightedPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  std::string why;
  const auto weighted = weightedKeptForces(scene, why);
  ASSERT_TRUE(weighted.has_value()) << why;
  const auto weightless =
      keptPokeForces(weightlessPokeScene(scene), "liver-fem.msh", "liver-fem-poke.csv", why);
  ASSERT_TRUE(weightless.has_value()) << why;
  for (std::size_t d = 0; d < weighted->size(); ++d) {
    if (d > 0) {
      EXPECT_GT((*weighted)[d], (*weighted)[d - 1]);
    }
    EXPECT_GT((*weighted)[d], 3.0 * (*weightless)[d]) << kWeightedDepths_mm[d] << " mm";
  }
  EXPECT_FALSE(weightedKeptForces(weightlessPokeScene(scene), why).has_value());
}

TEST(OrganPoke, TheFemAtItsOwnRateUnderGravityFollowsTheWeightedReference) {
  // The refined FEM scene given the default scene's weight and tray, its body refined to 2.5 mm
  // where the tool aims (the scene's 4 mm reads far too stiff under gravity:
  // docs/performance-details.md, "The liver under its weight against the continuum"): the poke
  // through the scene's own steps from the surface as it settled, against the weighted
  // reference. The first millimetre, where the taut surface first bends round the probe, is the
  // hardest.
  SceneDescription scene =
      heldAsTheDefaultScene(readScene(kAssets + "/scenes/liver-fem-refined.json"));
  ASSERT_TRUE(scene.tetMesh->refinement.has_value());
  scene.tetMesh->refinement->finest_m = 0.0025;
  std::string why;
  const auto reference = weightedKeptForces(scene, why);
  ASSERT_TRUE(reference.has_value()) << why;
  const SimulatorPoke poke = pokeSimulator(scene, kWeightedDepths_m, 0.002);
  EXPECT_NEAR(poke.force_N[0] / (*reference)[0], 1.0, 0.20);
  expectWithinAtEachDepth(poke, *reference, kWeightedDepths_mm, 0.10, 1);
}

TEST(OrganPoke, UnderGravityABodyRefinedTo2MmIsWithinTenPerCentGivenItsUpdatesTime) {
  // Refined to 2 mm growing 1 mm per mm, the body bends round the probe from the first
  // millimetre, but its updates take longer than the scene's 60 ms on a two-core machine: each
  // is used 150 ms after it starts, and the probe at 3 mm/s travels 0.45 mm an update, within
  // the scheme's reach under gravity (docs/performance-details.md, "Under gravity within 10 % at
  // every depth, given the update's time").
  SceneDescription scene =
      heldAsTheDefaultScene(readScene(kAssets + "/scenes/liver-fem-refined.json"));
  ASSERT_TRUE(scene.tetMesh->refinement.has_value());
  scene.tetMesh->refinement->finest_m = 0.002;
  scene.tetMesh->refinement->growth = 1.0;
  scene.femUpdateLatency_s = 0.15;
  std::string why;
  const auto reference = weightedKeptForces(scene, why);
  ASSERT_TRUE(reference.has_value()) << why;
  expectWithinAtEachDepth(pokeSimulator(scene, kWeightedDepths_m, 0.003), *reference,
                          kWeightedDepths_mm, 0.10);
}

TEST(OrganPoke, TheKeyChangesWithTheProbe) {
  const SceneDescription scene =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  OrganPokeSetup setup = organPokeSetup(scene, {0.001});
  const std::string mesh = kAssets + "/meshes/liver-fem.msh";
  const std::uint64_t key = femReferenceKey(scene, mesh, setup, 1e6);
  EXPECT_EQ(femReferenceKey(scene, mesh, setup, 1e6), key);
  EXPECT_NE(femReferenceKey(scene, mesh, setup, 2e6), key);
  setup.probeRadius_m *= 2.0;
  EXPECT_NE(femReferenceKey(scene, mesh, setup, 1e6), key);
}

TEST(OrganPoke, TheWeightedPokesKeyHasItsGravityTrayAndDensity) {
  // The bundled scene as it holds the liver (gravity and its tray): a reference of its own, keyed
  // apart from the weightless one, and apart again for each of what holds it up.
  const SceneDescription scene = weightedPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  const std::string mesh = kAssets + "/meshes/liver-fem.msh";
  const OrganPokeSetup setup = organPokeSetup(scene, {0.001}, 1060.0);
  ASSERT_TRUE(setup.tray.has_value());
  EXPECT_EQ(setup.gravity_m_s2, scene.gravity_m_s2);
  EXPECT_EQ(setup.tray->height_m, scene.tray->height_m);
  const std::uint64_t key = femReferenceKey(scene, mesh, setup, 1e6);
  const OrganPokeSetup weightless = organPokeSetup(weightlessPokeScene(scene), {0.001}, 1060.0);
  EXPECT_NE(femReferenceKey(scene, mesh, weightless, 1e6), key);
  for (const auto& change : std::vector<std::function<void(OrganPokeSetup&)>>{
           [](OrganPokeSetup& s) { s.gravity_m_s2.y() *= 2.0; },
           [](OrganPokeSetup& s) { s.density_kg_m3 = 1000.0; },
           [](OrganPokeSetup& s) { s.tray->height_m += 0.001; },
           [](OrganPokeSetup& s) { s.tray->stiffness_Pa_per_m *= 2.0; },
           [](OrganPokeSetup& s) { s.tray.reset(); }}) {
    OrganPokeSetup changed = setup;
    change(changed);
    EXPECT_NE(femReferenceKey(scene, mesh, changed, 1e6), key);
  }
  // Weighted needs gravity, and a frictionless tray as the reference's.
  EXPECT_THROW(weightedPokeScene(weightlessPokeScene(scene)), CommandError);
  SceneDescription gripping = scene;
  gripping.tray->friction = 0.5;
  EXPECT_THROW(weightedPokeScene(gripping), CommandError);
}

TEST(OrganPoke, TheMapsLiverPokeIsOrganPokesSimulatorAndIsMeasuredOnceForAnyThreadCount) {
  const BundledMapPoke setup;
  const SceneDescription& bundled = setup.bundled;
  const TradeSettings& settings = setup.settings;
  TradeErrors errors(setup.tissue, bundled, settings);
  const std::vector<TradeRow> rows = tradeRows(bundled, settings);
  ASSERT_GE(rows.size(), 2u);
  ASSERT_EQ(rows[0].knob, "resolution");
  ASSERT_EQ(rows[1].knob, "threads");
  TradeMeasurement twoThreads, oneThread;
  errors.measureOrgan(rows[0], twoThreads);
  errors.measureOrgan(rows[1], oneThread);
  ASSERT_EQ(twoThreads.organForce_N.size(), 2u);
  EXPECT_GT(twoThreads.organForce_N[0], 0.0);
  EXPECT_GT(twoThreads.organForce_N[1], twoThreads.organForce_N[0]);
  EXPECT_EQ(oneThread.organForce_N, twoThreads.organForce_N);
  // What organ-poke --springs 1000 measures: the same scene, made weightless, poked the same way.
  SceneDescription lattice = weightlessPokeScene(bundled);
  lattice.tetMesh.reset();
  lattice.targetSprings = 1000;
  const SimulatorPoke poke =
      pokeSimulator(lattice, settings.organDepths_m, settings.organSpeed_m_s);
  EXPECT_EQ(poke.force_N, twoThreads.organForce_N);
  // Its steps: at least those from 1 mm above the surface to the deepest depth, timed apart from
  // the start-up.
  EXPECT_GE(static_cast<double>(poke.steps),
            (0.001 + settings.organDepths_m.back()) / settings.organSpeed_m_s / lattice.timeStep_s);
  EXPECT_GT(poke.stepping_s, 0.0);
  EXPECT_LT(poke.stepping_s, poke.seconds);
  EXPECT_EQ(poke.stepTimes_ms.size(), static_cast<std::size_t>(poke.steps));
  // The first row's thread count timed the poke; the one-thread row shares its forces, not its
  // times.
  EXPECT_GT(twoThreads.organStepMedian_ms, 0.0);
  EXPECT_GE(twoThreads.organStepP99_ms, twoThreads.organStepMedian_ms);
  EXPECT_TRUE(std::isnan(oneThread.organStepMedian_ms));
}

TEST(OrganPoke, TheFemOnTheOrgansMeshIsARowOfTheLiverPokeWithItsCost) {
  BundledMapPoke setup;
  const SceneDescription& bundled = setup.bundled;
  TradeSettings& settings = setup.settings;
  // A twentieth of the steps, to 2 mm: the row's shape is what is checked here.
  settings.organSpeed_m_s = 0.04;
  settings.organDepths_m = {0.001, 0.002};
  const std::string mesh = kAssets + "/meshes/liver-graded-5mm.msh";
  settings.organMeshes = {OrganMesh{mesh, "graded"}};
  const std::vector<TradeRow> rows = tradeRows(bundled, settings);
  std::vector<const TradeRow*> organRows;
  for (const TradeRow& row : rows) {
    if (row.knob == "fem-organ") organRows.push_back(&row);
  }
  ASSERT_EQ(organRows.size(), 2u);
  EXPECT_EQ(organRows[0]->strainCells, "tets");
  EXPECT_EQ(organRows[1]->strainCells, "faces");
  EXPECT_EQ(organRows[0]->organMeshPath, mesh);
  EXPECT_DOUBLE_EQ(organRows[0]->bulkModulus_Pa, settings.organMeshBulkModulus_Pa);

  TradeErrors errors(setup.tissue, bundled, settings);
  TradeMeasurement measured;
  errors.measureOrgan(*organRows[0], measured);
  ASSERT_EQ(measured.organForce_N.size(), 2u);
  EXPECT_GT(measured.organForce_N[0], 0.0);
  EXPECT_GT(measured.organForce_N[1], measured.organForce_N[0]);
  EXPECT_EQ(measured.cost.nodes, 912);
  EXPECT_GT(measured.cost.stepMedian_ms, 0.0);
  EXPECT_DOUBLE_EQ(measured.cost.stepMedian_ms, measured.organStepMedian_ms);
  EXPECT_GT(measured.cost.startup_s, 0.0);
  EXPECT_GT(measured.cost.stepsPerSecond, 0.0);

  // What organ-poke measures on a scene that sets the same up in its file: the FEM per tet on
  // that mesh, no drawn surface, a volume per node, no softening.
  SceneDescription scene = weightlessPokeScene(bundled);
  scene.surface.reset();
  scene.tetMesh = SceneMeshSource{mesh, 1.0, "", std::nullopt};
  scene.model = "fem";
  scene.isSoftening = false;
  scene.volumeCells = "nodes";
  scene.bulkModulus_Pa = settings.organMeshBulkModulus_Pa;
  const SimulatorPoke poke = pokeSimulator(scene, settings.organDepths_m, settings.organSpeed_m_s);
  EXPECT_EQ(poke.force_N, measured.organForce_N);
  EXPECT_EQ(poke.nodes, 912);
}

TEST(OrganPoke, TheReferencesElementOnTheOrgansMeshIsARowSolvedOnceAndTimedEachMap) {
  BundledMapPoke setup;
  TradeSettings& settings = setup.settings;
  // One load step each, on a coarse mesh of the organ: the row's shape is what is checked here.
  settings.organDepths_m = {0.0005, 0.001};
  settings.tetBulkModulus_Pa = defaultFemBulkModulus(setup.tissue.energy);
  const std::string mesh = std::string(TISSUESIM_TEST_DATA_DIR) + "/meshes/liver-fem-coarse.msh";
  settings.organMeshes = {OrganMesh{mesh, "coarse"}};
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() /
      ("organ-quadratic-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  settings.organCacheFolder = folder.string();
  const std::vector<TradeRow> rows = tradeRows(setup.bundled, settings);
  std::vector<const TradeRow*> quadratic;
  for (const TradeRow& row : rows) {
    if (row.knob == "fem-quadratic") quadratic.push_back(&row);
  }
  ASSERT_EQ(quadratic.size(), 1u);
  const TradeRow& row = *quadratic.front();
  EXPECT_TRUE(row.isQuadratic());
  EXPECT_TRUE(row.isOnOrganMesh());
  EXPECT_EQ(row.organMeshPath, mesh);
  EXPECT_DOUBLE_EQ(row.bulkModulus_Pa, settings.tetBulkModulus_Pa);

  // Its forces are organ-poke's FEM on that mesh.
  const SceneDescription weightless = weightlessPokeScene(setup.bundled);
  const IndentationCurve fem =
      pokeOrganFem(setup.tissue.energy, readTetMesh(mesh),
                   organPokeSetup(weightless, settings.organDepths_m), settings.tetBulkModulus_Pa);
  TradeErrors errors(setup.tissue, setup.bundled, settings);
  TradeMeasurement solved;
  errors.measureOrgan(row, solved);
  EXPECT_EQ(solved.organForce_N, fem.force_N);
  ASSERT_EQ(solved.organForce_N.size(), 2u);
  EXPECT_GT(solved.organForce_N[1], solved.organForce_N[0]);
  EXPECT_GT(solved.organForce_N[0], 0.0);
  EXPECT_EQ(solved.organEvents, 0);
  EXPECT_EQ(solved.cost.nodes, fem.nodes);  // the quadratic mesh's, edges' midpoints included
  // Its step is a Newton iteration.
  EXPECT_GT(solved.organStepMedian_ms, 0.0);
  EXPECT_DOUBLE_EQ(solved.cost.stepMedian_ms, solved.organStepMedian_ms);
  EXPECT_NEAR(solved.organStepsPerSecond * solved.organStepMedian_ms, 1e3, 1e-6);
  EXPECT_TRUE(std::isnan(solved.organStepP99_ms));

  // Kept in the folder under its key, and read from there by the next map (forces doubled in
  // the file here, to tell a read from a solve), which times its iterations again.
  const std::string kept = (folder / "liver-fem-coarse-poke.csv").string();
  std::string keyLine;
  ASSERT_TRUE(std::getline(std::ifstream(kept) >> std::ws, keyLine));
  std::ofstream(kept) << std::setprecision(17) << keyLine << "\ndepth_mm,fem_force_n\n0.5,"
                      << 2.0 * fem.force_N[0] << "\n1," << 2.0 * fem.force_N[1] << "\n";
  TradeMeasurement read;
  errors.measureOrgan(row, read);
  ASSERT_EQ(read.organForce_N.size(), 2u);
  EXPECT_DOUBLE_EQ(read.organForce_N[0], 2.0 * fem.force_N[0]);
  EXPECT_DOUBLE_EQ(read.organForce_N[1], 2.0 * fem.force_N[1]);
  EXPECT_GT(read.organStepMedian_ms, 0.0);
  // A kept file for other inputs is not used: the row is solved again, to the same forces.
  std::ofstream(kept) << "# organ-poke fem reference, key 0000000000000000\ndepth_mm,fem_force_n\n"
                         "0.5,1\n1,2\n";
  TradeMeasurement again;
  errors.measureOrgan(row, again);
  EXPECT_EQ(again.organForce_N, solved.organForce_N);
  std::filesystem::remove_all(folder);
}

TEST(OrganPoke, TheFemSceneAtItsOwnRateIsARowOnTheLiverAndTheBlock) {
  // The bundled refined FEM scene as the map's row: to 1 mm on the liver through the scene's own
  // steps, and to 0.5 mm on the block through the same scheme and settings on indent's body;
  // each as organ-poke and indent measure them.
  BundledMapPoke setup;
  TradeSettings& settings = setup.settings;
  settings.organDepths_m = {0.0005, 0.001};
  settings.organSpeed_m_s = 0.004;
  settings.depths_m = {0.0005};
  const std::string scenePath = kAssets + "/scenes/liver-fem-refined.json";
  settings.hapticRateScene = readScene(scenePath);
  const std::vector<TradeRow> rows = tradeRows(setup.bundled, settings);
  std::vector<const TradeRow*> hapticRate;
  for (const TradeRow& row : rows) {
    if (row.knob == "fem-haptic-rate") hapticRate.push_back(&row);
  }
  ASSERT_EQ(hapticRate.size(), 1u);
  const TradeRow& row = *hapticRate.front();
  const SceneDescription scene = weightlessPokeScene(readScene(scenePath));
  EXPECT_TRUE(row.isHapticRate());
  EXPECT_TRUE(row.isOnOrganMesh());
  EXPECT_FALSE(row.isQuadratic());
  EXPECT_EQ(row.organMeshPath, scene.tetMesh->file.string());
  EXPECT_DOUBLE_EQ(row.bulkModulus_Pa, scene.bulkModulus_Pa);
  EXPECT_EQ(row.newtonIterations, scene.newtonIterations);
  settings.hapticRateScene.reset();
  for (const TradeRow& without : tradeRows(setup.bundled, settings))
    EXPECT_NE(without.knob, "fem-haptic-rate");
  settings.hapticRateScene = readScene(kAssets + "/scenes/liver-poke.json");  // springs: refused
  EXPECT_THROW(tradeRows(setup.bundled, settings), CommandError);
  settings.hapticRateScene = readScene(scenePath);

  TradeErrors errors(setup.tissue, setup.bundled, settings);
  TradeMeasurement measured;
  errors.measureOrgan(row, measured);
  EXPECT_TRUE(measured.failure.empty()) << measured.failure;
  ASSERT_EQ(measured.organForce_N.size(), 2u);
  EXPECT_GT(measured.organForce_N[0], 0.0);
  EXPECT_GT(measured.organForce_N[1], measured.organForce_N[0]);
  // Its step is the scene's: well under a millisecond, against an update of tens of them, even
  // at the 99th percentile, whose steps taking an update in no longer wait for it here (run
  // faster than real time, each waits for the update its latency has it take).
  EXPECT_GT(measured.organStepMedian_ms, 0.0);
  EXPECT_LE(measured.organStepMedian_ms, measured.organStepP99_ms);
  EXPECT_LT(10.0 * measured.organStepP99_ms, measured.organUpdateMean_ms);
  EXPECT_DOUBLE_EQ(measured.cost.stepMedian_ms, measured.organStepMedian_ms);
  EXPECT_GT(measured.cost.startup_s, 0.0);
  EXPECT_EQ(measured.cost.events, measured.organEvents);
  // The liver: organ-poke's through the same scene.
  const SimulatorPoke direct =
      pokeSimulator(scene, settings.organDepths_m, settings.organSpeed_m_s);
  EXPECT_EQ(measured.cost.nodes, direct.nodes);
  EXPECT_EQ(measured.organForce_N, direct.force_N);
  EXPECT_EQ(measured.organEvents, direct.events);
  // The block: indent's fem-haptic-rate with the scene's settings, in the static column.
  IndentationSetup block;
  block.depths_m = settings.depths_m;
  HapticRateSettings rate;
  rate.speed_m_s = settings.organSpeed_m_s;
  rate.newtonIterations = scene.newtonIterations;
  rate.updateLatency_s = scene.femUpdateLatency_s;
  const HapticRatePoke indented = indentHapticRate(
      setup.tissue.energy, block, IndentationBodyGrading{}, scene.bulkModulus_Pa, 0.001, rate);
  EXPECT_EQ(measured.staticForce_N, indented.force_N);
  EXPECT_TRUE(measured.paceForce_N.empty());
}

}  // namespace
}  // namespace tissuesim::app
