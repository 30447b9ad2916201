// SPDX-License-Identifier: Apache-2.0
// The liver poke's kept FEM reference (assets/meshes/liver-fem-poke.csv, which `trade` reads and
// `measure` passes to organ-poke) belongs to the bundled scene as it is: a change to its tissue,
// its instrument, its fixed region, the conformal mesh or the reference's solver changes the key,
// and this test fails until the reference is solved again (assets/meshes/README.md).

#include "app/OrganPoke.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/FemForceCache.h"
#include "app/LoadedTissue.h"
#include "app/SceneSession.h"
#include "fem/FemModel.h"

namespace tissuesim::app {
namespace {

const std::string kAssets = TISSUESIM_ASSET_DIR;

TEST(OrganPoke, TheBundledLiverPokesKeptReferenceIsTheBundledScenes) {
  const SceneDescription scene =
      weightlessPokeScene(readScene(kAssets + "/scenes/liver-poke.json"));
  const LoadedTissue tissue(scene.tissue.string());
  std::vector<double> depths_m;
  for (const double depth : kOrganPokeDepths_mm) depths_m.push_back(depth / 1000.0);
  const std::uint64_t key =
      femReferenceKey(scene, kAssets + "/meshes/liver-fem.msh", organPokeSetup(scene, depths_m),
                      defaultFemBulkModulus(tissue.energy));
  std::string why;
  const auto forces =
      readFemForceCache(kAssets + "/meshes/liver-fem-poke.csv", key, kOrganPokeDepths_mm, why);
  ASSERT_TRUE(forces.has_value()) << why;
  // The continuum stiffens with depth under the probe.
  for (std::size_t d = 1; d < forces->size(); ++d) EXPECT_GT((*forces)[d], (*forces)[d - 1]);
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

}  // namespace
}  // namespace tissuesim::app
