// SPDX-License-Identifier: Apache-2.0
// Every tissue the file's validation admits runs in the bundled scene: the corners of the
// admitted ranges (AdmittedTissueCorners.h) through start-up (calibration, tables, the settled
// start under gravity) and a poke, with every step good and the state finite. What start-up
// cannot use would have to be refused with a reason; none of the corners is.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "collision/CapsuleContact.h"
#include "sim/InstrumentScript.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"
#include "support/AdmittedTissueCorners.h"

namespace tissuesim {
namespace {

TEST(AdmittedTissueScenes, EveryCornerStartsAndTakesAPokeWithFiniteSteps) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("tissuesim-corners-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::vector<test::TissueCorner> corners = test::admittedTissueCorners();
  for (const test::TissueCorner& corner : corners) {
    SCOPED_TRACE(corner.what);
    const std::filesystem::path tissue = folder / "tissue.json";
    std::ofstream(tissue) << test::tissueJson(corner);
    SceneDescription scene =
        loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
    scene.tissue = tissue;
    scene.tetMesh->file = std::string(TISSUESIM_ASSET_DIR) + "/meshes/liver-1000.msh";
    Simulation simulation(scene);
    EXPECT_TRUE(std::isfinite(simulation.stiffnessScale()) && simulation.stiffnessScale() > 0.0)
        << simulation.stiffnessScale();
    ASSERT_TRUE(simulation.state().isFinite()) << "the settled start";
    const SceneInstrument& tool = *simulation.scene().instrument;
    // 5 cm along the tool in 0.5 s: about 1.5 cm into the sagged anterior lobe.
    InstrumentScript script = InstrumentScript::poke({tool.tipStart_m, tool.direction}, 0.05, 0.5);
    std::unique_ptr<CapsuleContact> contact = makeInstrumentContact(simulation);
    simulation.setContactProvider(contact.get());
    simulation.setInstrumentSource(&script);
    double peak_N = 0.0;
    for (int n = 0; n < 500; ++n) {
      const StepOutcome outcome = simulation.step();
      peak_N = std::max(peak_N, outcome.contact.toolForce_N.norm());
      ASSERT_TRUE(outcome.isGood) << "step " << n << ": " << outcome.integrator.reason;
      ASSERT_TRUE(std::isfinite(outcome.contact.toolForce_N.norm())) << "step " << n;
    }
    EXPECT_TRUE(simulation.state().isFinite());
    if (&corner == &corners.front()) {
      EXPECT_GT(peak_N, 0.1) << "the poke reaches the liver";
    }
  }
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace tissuesim
