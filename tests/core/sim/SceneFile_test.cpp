// SPDX-License-Identifier: Apache-2.0
#include "sim/SceneFile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace tissuesim {
namespace {

inline std::string scenePath(const std::string& name) {
  return std::string(TISSUESIM_TEST_DATA_DIR) + "/scenes/" + name;
}

TEST(SceneFile, TheBundledSceneLoads) {
  const SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
  EXPECT_EQ(scene.name, "liver poke");
  ASSERT_TRUE(scene.surface.has_value());
  EXPECT_DOUBLE_EQ(scene.surface->metresPerUnit, 0.03);
  ASSERT_TRUE(scene.tetMesh.has_value());
  EXPECT_TRUE(std::filesystem::exists(scene.tetMesh->file));
  ASSERT_TRUE(scene.fixed.box_m.has_value());
  EXPECT_EQ(scene.gravity_m_s2, Eigen::Vector3d(0.0, -9.81, 0.0));  // it rests on its tray
  ASSERT_TRUE(scene.tray.has_value());
  EXPECT_EQ(scene.tray->up, Eigen::Vector3d::UnitY());
  EXPECT_DOUBLE_EQ(scene.tray->height_m, 0.0075);
  EXPECT_DOUBLE_EQ(scene.tray->stiffness_Pa_per_m, 3e7);
  EXPECT_EQ(scene.tray->friction, 0.0);  // frictionless: a poke leaves no set where it rests
  ASSERT_TRUE(scene.instrument.has_value());
  EXPECT_DOUBLE_EQ(scene.instrument->shaftRadius_m, 0.0025);
  EXPECT_NEAR(scene.instrument->direction.norm(), 1.0, 1e-15);
  EXPECT_TRUE(scene.isSoftening);
  EXPECT_EQ(scene.bulkModulus_Pa, 1e5);  // the volume term: the liver recovers from any poke
  EXPECT_DOUBLE_EQ(scene.timeStep_s, 1e-3);
}

TEST(SceneFile, WhatAMinimalSceneLeavesOutIsNotThere) {
  const SceneDescription scene = loadSceneFile(scenePath("minimal.json"));
  EXPECT_FALSE(scene.surface.has_value());
  EXPECT_FALSE(scene.instrument.has_value());
  EXPECT_FALSE(scene.fixed.box_m.has_value());
  EXPECT_TRUE(scene.fixed.nodes.empty());
  EXPECT_EQ(scene.gravity_m_s2, Eigen::Vector3d::Zero());
  EXPECT_FALSE(scene.tray.has_value());
  EXPECT_EQ(scene.model, "springs");
  EXPECT_TRUE(scene.isSoftening);
  const SceneDescription fem = loadSceneFile(scenePath("fem.json"));
  EXPECT_EQ(fem.model, "fem");
  EXPECT_FALSE(fem.isSoftening);  // the FEM has none: off unless asked, and refused if asked
  EXPECT_EQ(fem.bulkModulus_Pa, 100e3);
  EXPECT_EQ(scene.assessment.toolForceThreshold_N, 8.0);
  EXPECT_FALSE(scene.assessment.damageStretch.has_value());  // the tissue's
  const SceneDescription assessed = loadSceneFile(scenePath("assessment.json"));
  EXPECT_EQ(assessed.assessment.toolForceThreshold_N, 3.5);
  EXPECT_EQ(assessed.assessment.damageStretch, 1.25);
  // Quasi-Newton takes gravity and a tray (Simulation.QuasiNewtonPokesTheLiverAsImplicitEulerDoes).
  const SceneDescription heavy = loadSceneFile(scenePath("quasi-newton-gravity.json"));
  EXPECT_EQ(heavy.integrator, "quasi-newton");
  EXPECT_EQ(heavy.gravity_m_s2, Eigen::Vector3d(0.0, -9.81, 0.0));
  const SceneDescription onTray = loadSceneFile(scenePath("quasi-newton-tray.json"));
  EXPECT_EQ(onTray.integrator, "quasi-newton");
  ASSERT_TRUE(onTray.tray.has_value());
  const SceneDescription nodal = loadSceneFile(scenePath("fem-nodal-volume.json"));
  EXPECT_EQ(nodal.volumeCells, "nodes");
  EXPECT_EQ(nodal.strainCells, "tets");
  EXPECT_EQ(loadSceneFile(scenePath("fem.json")).volumeCells, "cubes");
  EXPECT_EQ(loadSceneFile(scenePath("fem-face-strain.json")).strainCells, "faces");
  const SceneDescription hapticRate = loadSceneFile(scenePath("fem-haptic-rate.json"));
  EXPECT_EQ(hapticRate.model, "fem-haptic-rate");
  EXPECT_TRUE(hapticRate.isSoftening) << "it softens per material point unless told not to";
  EXPECT_FALSE(loadSceneFile(scenePath("fem.json")).isSoftening) << "the lattice's FEM does not";
  EXPECT_DOUBLE_EQ(hapticRate.femUpdateLatency_s, 0.05);
  // The defaults: updates used a fixed 100 ms after they start (deterministic), two Newton
  // iterations each (the reach of docs/scene-file.md at any bulk modulus).
  const SceneDescription byDefault = loadSceneFile(scenePath("fem-haptic-rate-defaults.json"));
  EXPECT_DOUBLE_EQ(byDefault.femUpdateLatency_s, 0.1);
  EXPECT_EQ(byDefault.newtonIterations, 2);
  // Its body under gravity on a (frictionless) tray.
  const SceneDescription heavyHapticRate = loadSceneFile(scenePath("fem-haptic-rate-gravity.json"));
  EXPECT_EQ(heavyHapticRate.gravity_m_s2, Eigen::Vector3d(0.0, -9.81, 0.0));
  ASSERT_TRUE(heavyHapticRate.tray.has_value());
  EXPECT_EQ(heavyHapticRate.tray->friction, 0.0);
  const SceneDescription generated = loadSceneFile(scenePath("generated.json"));
  EXPECT_EQ(generated.targetSprings, 1000);
  EXPECT_FALSE(generated.tetMesh.has_value());
}

struct BadScene {
  const char* file;
  const char* expected;
};

class BadSceneFile : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneFile, IsRefusedWithOneLine) {
  const std::string path = scenePath(GetParam().file);
  try {
    loadSceneFile(path);
    FAIL() << "accepted";
  } catch (const SceneFileError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadSceneFile,
    ::testing::Values(
        BadScene{"empty.json", "the file is empty"}, BadScene{"not-json.json", "not valid JSON"},
        BadScene{"missing-tissue.json", "field 'tissue' names"},
        BadScene{"short-gravity.json", "field 'gravity_m_s2' must be an array of three numbers"},
        BadScene{"empty-box.json", "field 'fixed_region.box_max_m' must exceed box_min_m"},
        BadScene{"unknown-integrator.json", "field 'physics.integrator' = \"rk4\""},
        BadScene{"fractional-threads.json", "field 'physics.threads' = 2.5"},
        BadScene{"unknown-key.json", "field 'gravity' is not a known field"},
        BadScene{"negative-scale.json", "field 'surface.metres_per_unit' = -1 is out of range"},
        BadScene{"no-tet-mesh.json", "field 'tet_mesh' is missing"},
        BadScene{"both-meshes.json", "are both given"},
        BadScene{"zero-direction.json", "field 'instrument.direction' must not be the zero vector"},
        BadScene{"tray-zero-up.json", "field 'tray.up' must not be the zero vector"},
        BadScene{"tray-no-height.json", "field 'tray.height_m' is missing"},
        BadScene{"tray-zero-stiffness.json", "field 'tray.stiffness_pa_per_m' = 0 is out of range"},
        BadScene{"tray-negative-friction.json", "field 'tray.friction' = -0.2 is out of range"},
        BadScene{"unknown-model.json",
                 "field 'effects.model' = \"mpm\"; expected springs, fem or fem-haptic-rate"},
        BadScene{"fem-haptic-rate-tray.json",
                 "field 'tray.friction' is not modelled with effects.model fem-haptic-rate"},
        BadScene{"fem-haptic-rate-no-instrument.json",
                 "field 'instrument' is missing; effects.model fem-haptic-rate is the probe's"},
        BadScene{
            "fem-haptic-rate-late.json",
            "field 'physics.fem_update_latency_ms' = 5000 is out of range; expected 0 to 1000"},
        BadScene{"fem-haptic-rate-unheld.json",
                 "field 'fixed_region' is missing; effects.model fem-haptic-rate holds the body"},
        BadScene{"fem-latency-springs.json",
                 "field 'physics.fem_update_latency_ms' is for effects.model fem-haptic-rate"},
        BadScene{"fem-softening.json",
                 "field 'effects.softening' must be false with model fem, which has no softening"},
        BadScene{"fem-no-volume.json",
                 "field 'effects.volume_term_kpa' must be > 0 with model fem"},
        BadScene{"fem-quasi-newton.json",
                 "field 'physics.integrator' = \"quasi-newton\" is for the springs model"},
        BadScene{"nodal-volume-unknown.json",
                 "field 'effects.volume_cells' = \"tets\"; expected cubes or nodes"},
        BadScene{"strain-cells-unknown.json",
                 "field 'effects.strain_cells' = \"cubes\"; expected tets, faces or nodes"},
        BadScene{"strain-cells-springs.json",
                 "field 'effects.strain_cells' = \"nodes\" is for model fem"},
        BadScene{"nodal-volume-no-kappa.json",
                 "field 'effects.volume_cells' = \"nodes\" needs volume_term_kpa above 0"},
        BadScene{"nodal-volume-quasi-newton.json",
                 "field 'physics.integrator' = \"quasi-newton\" takes the volume term per cube"},
        BadScene{"assessment-zero-force.json",
                 "field 'assessment.force_threshold_n' = 0 is out of range"},
        BadScene{"assessment-damage-below-one.json",
                 "field 'assessment.damage_stretch' = 0.95 is out of range; expected a finite "
                 "number > 1"},
        BadScene{"assessment-unknown.json",
                 "field 'assessment.force_threshold' is not a known field"},
        BadScene{"refine-no-surface.json",
                 "field 'tet_mesh.refine_towards_tool' needs a 'surface'"},
        BadScene{"refine-no-instrument.json",
                 "field 'tet_mesh.refine_towards_tool' needs an 'instrument'"},
        BadScene{"refine-too-fine.json",
                 "field 'tet_mesh.refine_towards_tool.finest_mm' must be at least 0.1"},
        BadScene{"refine-coarsest-below-finest.json",
                 "field 'tet_mesh.refine_towards_tool.coarsest_mm' must be at least finest_mm"},
        BadScene{"refine-unknown.json",
                 "field 'tet_mesh.refine_towards_tool.finest' is not a known field"},
        BadScene{"refine-surface.json", "field 'surface.refine_towards_tool' is not a known field"},
        BadScene{"does-not-exist.json", "cannot open the scene file"}),
    [](const auto& scene) {
      std::string name = scene.param.file;
      name = name.substr(0, name.find('.'));
      for (char& c : name) c = c == '-' ? '_' : c;
      return name;
    });

}  // namespace
}  // namespace tissuesim

#include "mesh/SurfaceReader.h"
#include "mesh/TetMeshFile.h"
#include "sim/SceneGeometry.h"

namespace tissuesim {
namespace {

TEST(SceneGeometry, TheBundledSceneBuildsItsMeshSurfaceAndClamp) {
  const SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
  const SceneGeometry geometry = loadSceneGeometry(scene);
  EXPECT_EQ(countUniqueEdges(geometry.mesh), 5296);
  ASSERT_TRUE(geometry.surface.has_value());
  EXPECT_EQ(geometry.surface->vertexCount(), 2194);  // welded from assimp's per-corner vertices
  ASSERT_TRUE(geometry.embedding.has_value());
  // Vertices outside the lattice lie within one cube diagonal (12.1 mm x sqrt 3) of it.
  EXPECT_LT(geometry.embedding->maxOutsideDistance_m(), 0.0121 * std::sqrt(3.0));
  EXPECT_GE(geometry.fixedNodes.size(), 10u);
  EXPECT_LT(geometry.fixedNodes.size(), static_cast<std::size_t>(geometry.mesh.nodeCount() / 4));
  for (const int node : geometry.fixedNodes) {
    EXPECT_TRUE(scene.fixed.box_m->contains(geometry.mesh.nodes_m.col(node)));
  }
}

TEST(SceneGeometry, AMinimalSceneBuildsNoSurface) {
  const SceneGeometry geometry = loadSceneGeometry(loadSceneFile(scenePath("minimal.json")));
  EXPECT_FALSE(geometry.surface.has_value());
  EXPECT_FALSE(geometry.embedding.has_value());
  EXPECT_TRUE(geometry.fixedNodes.empty());
}

TEST(SceneGeometry, GeneratesAMeshFromTheSurface) {
  const SceneGeometry geometry = loadSceneGeometry(loadSceneFile(scenePath("generated.json")));
  EXPECT_NEAR(static_cast<double>(countUniqueEdges(geometry.mesh)), 1000.0, 100.0);
}

TEST(SceneGeometry, AMeshWithoutAUnitIsScaledByItsSizeAndSaysSo) {
  // minimal.json gives the 1,000-spring liver (metres) no metres_per_unit: read as metres, said.
  const SceneGeometry minimal = loadSceneGeometry(loadSceneFile(scenePath("minimal.json")));
  const TetMesh inMetres =
      readTetMesh(std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-1000.msh", 1.0);
  EXPECT_LT((minimal.mesh.nodes_m - inMetres.nodes_m).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(minimal.assumptions.size(), 1u);
  EXPECT_NE(minimal.assumptions[0].find("liver-1000.msh: assumed metres"), std::string::npos)
      << minimal.assumptions[0];
  EXPECT_NE(minimal.assumptions[0].find("metres_per_unit"), std::string::npos);

  // The bundled smooth liver is about 6 units across (the scene says 3 cm a unit): without
  // that, centimetres is the organ-sized guess.
  SceneDescription scene = loadSceneFile(scenePath("generated.json"));
  const std::filesystem::path surfaceFile = scene.surface->file;
  scene.surface->metresPerUnit = 0.0;
  const SceneGeometry guessed = loadSceneGeometry(scene);
  ASSERT_EQ(guessed.assumptions.size(), 1u);
  EXPECT_NE(guessed.assumptions[0].find("assumed centimetres"), std::string::npos)
      << guessed.assumptions[0];
  const auto diagonal = [](const Eigen::Matrix3Xd& p) {
    return (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  };
  const double inUnits = diagonal(readSurface(surfaceFile, {1.0, ""}).vertices_m);
  EXPECT_NEAR(diagonal(guessed.surface->vertices_m), 0.01 * inUnits, 1e-9);

  // A scale the scene states is used as it is, and nothing is assumed.
  EXPECT_TRUE(
      loadSceneGeometry(loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"))
          .assumptions.empty());
}

TEST(SceneGeometry, AMeshFarFromTheOriginInItsGuessedUnitIsRefused) {
  // 0.2 units across (metres, by its size) but 10,000 units from the origin: 10 km.
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("tissuesim-units-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::filesystem::path huge = folder / "huge.obj";
  {
    std::ofstream out(huge);
    out << "v 1e4 0 0\nv 10000.2 0 0\nv 1e4 0.2 0\nv 1e4 0 0.2\n"
           "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  }
  SceneDescription scene = loadSceneFile(scenePath("minimal.json"));
  scene.surface = SceneMeshSource{huge, 0.0, "", std::nullopt};
  try {
    loadSceneGeometry(scene);
    ADD_FAILURE() << "a surface 10 km from the origin was accepted";
  } catch (const SceneFileError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("huge.obj"), std::string::npos) << message;
    EXPECT_NE(message.find("from the origin in metres, the unit its size suggests"),
              std::string::npos)
        << message;
  }
  std::filesystem::remove_all(folder);
}

TEST(SceneGeometry, TheRefinedScenesMeshIsFineWhereTheToolAimsAndFollowsIt) {
  const SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-refined.json");
  ASSERT_TRUE(scene.tetMesh->refinement.has_value());
  EXPECT_DOUBLE_EQ(scene.tetMesh->refinement->finest_m, 0.004);
  const TetMesh file = readTetMesh(scene.tetMesh->file);
  const Eigen::Vector3d down(0.0, -1.0, 0.0);
  // The longest edge with its midpoint within 5 mm of where the axis meets the drawn surface, and
  // how far the mesh's own boundary lies below that point along the axis.
  const auto nearAim = [&](const SceneGeometry& geometry, const Eigen::Vector3d& tip,
                           double& longest_m, double& boundaryBelow_m) {
    Eigen::Vector3d aim, boundary;
    ASSERT_TRUE(
        firstCrossing(geometry.surface->vertices_m, geometry.surface->triangles, tip, down, aim));
    ASSERT_TRUE(
        firstCrossing(geometry.mesh.nodes_m, boundaryFaces(geometry.mesh), tip, down, boundary));
    boundaryBelow_m = aim.y() - boundary.y();
    longest_m = 0.0;
    const TetMesh& mesh = geometry.mesh;
    for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
      for (int a = 0; a < 4; ++a) {
        for (int b = a + 1; b < 4; ++b) {
          const Eigen::Vector3d p = mesh.nodes_m.col(mesh.tets(a, t));
          const Eigen::Vector3d q = mesh.nodes_m.col(mesh.tets(b, t));
          if ((0.5 * (p + q) - aim).norm() < 0.005) longest_m = std::max(longest_m, (q - p).norm());
        }
      }
    }
  };
  const SceneGeometry refined = loadSceneGeometry(scene);
  EXPECT_GT(refined.mesh.nodeCount(), file.nodeCount());
  // Bisected to a sixth of its edges' length, the mesh's worst tet keeps a quarter of the file's
  // radius ratio, and none is inverted (the boundary's moves onto the surface included).
  const double fileRadiusRatio = inspectTets(file).minRadiusRatio;
  EXPECT_GT(inspectTets(refined.mesh).minRadiusRatio, 0.25 * fileRadiusRatio);
  EXPECT_TRUE(inspectTets(refined.mesh).invertedTets.empty());
  double longest_m = 0.0, below_m = 0.0;
  nearAim(refined, scene.instrument->tipStart_m, longest_m, below_m);
  EXPECT_GT(longest_m, 0.0);
  EXPECT_LE(longest_m, 0.004 + 0.005 * 2.0 * 2.0);  // the bound at 5 mm from the aim
  // The coarse boundary's chord lies 2.4 mm inside the drawn surface there; moved onto it, 0.1.
  EXPECT_LT(std::abs(below_m), 2e-4);
  for (const int node : refined.fixedNodes)
    EXPECT_TRUE(scene.fixed.box_m->contains(refined.mesh.nodes_m.col(node)));

  SceneDescription unrefined = scene;
  unrefined.tetMesh->refinement.reset();
  const SceneGeometry coarse = loadSceneGeometry(unrefined);
  EXPECT_EQ(coarse.mesh.nodeCount(), file.nodeCount());
  double coarseLongest_m = 0.0, coarseBelow_m = 0.0;
  nearAim(coarse, scene.instrument->tipStart_m, coarseLongest_m, coarseBelow_m);
  EXPECT_GT(coarseLongest_m, 0.015);
  EXPECT_GT(coarseBelow_m, 1e-3);

  // The tool started 4 cm along x: the fine mesh is there now.
  SceneDescription moved = scene;
  moved.instrument->tipStart_m = Eigen::Vector3d(-0.04, 0.152, 0.045);
  const SceneGeometry there = loadSceneGeometry(moved);
  EXPECT_GT(inspectTets(there.mesh).minRadiusRatio, 0.25 * fileRadiusRatio);
  EXPECT_TRUE(inspectTets(there.mesh).invertedTets.empty());
  nearAim(there, moved.instrument->tipStart_m, longest_m, below_m);
  EXPECT_LE(longest_m, 0.004 + 0.005 * 2.0 * 2.0);
  EXPECT_LT(std::abs(below_m), 2e-4);

  // Listed fixed nodes hold the nodes the refinement put between them.
  SceneDescription listed = scene;
  listed.fixed.box_m.reset();
  for (int node = 0; node < file.nodeCount(); ++node) listed.fixed.nodes.push_back(node);
  EXPECT_EQ(static_cast<Eigen::Index>(loadSceneGeometry(listed).fixedNodes.size()),
            refined.mesh.nodeCount());

  SceneDescription missing = scene;
  missing.instrument->tipStart_m = Eigen::Vector3d(1.0, 0.152, 0.045);
  try {
    loadSceneGeometry(missing);
    ADD_FAILURE() << "a refinement aimed past the organ was accepted";
  } catch (const SceneFileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("'tet_mesh.refine_towards_tool': the instrument's "
                        "axis from tip_start_m along its direction misses"),
              std::string::npos)
        << error.what();
  }
}

TEST(SceneGeometry, AFixedBoxThatSelectsNothingIsRefused) {
  SceneDescription scene = loadSceneFile(scenePath("minimal.json"));
  scene.fixed.box_m = Eigen::AlignedBox3d(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6));
  EXPECT_THROW(loadSceneGeometry(scene), SceneFileError);
  scene.fixed.box_m.reset();
  scene.fixed.nodes = {100000};
  EXPECT_THROW(loadSceneGeometry(scene), SceneFileError);
}

}  // namespace
}  // namespace tissuesim
