// SPDX-License-Identifier: Apache-2.0
// A scene made ready to step (app/SceneSession.h): a new tissue in the FEM at its own rate
// sets the window's tool limit afresh.

#include "app/SceneSession.h"

#include <gtest/gtest.h>

#include "material/TissueFile.h"
#include "sim/HapticRateReach.h"

namespace tissuesim::app {
namespace {

TEST(SceneSession, ANewTissueSetsTheFemAtItsOwnRatesToolLimitAfresh) {
  // The bundled scene's one Newton iteration an update follows 0.36 mm an update on a volume
  // term at most a tenth of the reference's, which the tissue's stiffest tangent sets. A tissue
  // half as stiff halves the reference's bulk modulus: the scene's 26,000 kPa is then more than
  // a tenth of it, the iteration follows 0.3 mm, and the tool is held to 5 mm/s; back to
  // the bundled tissue, back to the bundled limit.
  SceneSession session(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-haptic-rate.json", "",
                       InstrumentDriver::Live);
  ASSERT_NE(session.liveInstrument(), nullptr);
  const double bundled_m_s = session.liveInstrument()->nearSpeed_m_s();
  EXPECT_NEAR(bundled_m_s, 0.00036 / 0.06, 1e-12);
  const TissueParameters bundled = session.simulation().parameters();
  TissueParameters softer = bundled;
  softer.mu_Pa *= 0.5;
  softer.A1_Pa *= 0.5;
  softer.A2_Pa *= 0.5;
  session.replaceTissue(softer);
  EXPECT_EQ(session.simulation().parameters().mu_Pa, softer.mu_Pa);
  EXPECT_NEAR(session.liveInstrument()->nearSpeed_m_s(), 0.0003 / 0.06, 1e-12);
  EXPECT_EQ(session.liveInstrument()->nearSpeed_m_s(),
            hapticRateToolSpeed_m_s(session.simulation().scene(), session.simulation().energy()));
  session.replaceTissue(bundled);
  EXPECT_EQ(session.liveInstrument()->nearSpeed_m_s(), bundled_m_s);
}

}  // namespace
}  // namespace tissuesim::app
