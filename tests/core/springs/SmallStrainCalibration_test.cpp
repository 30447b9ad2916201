// SPDX-License-Identifier: Apache-2.0
#include "springs/SmallStrainCalibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

#include "analysis/TensileExperiment.h"
#include "mesh/BlockMesher.h"
#include "springs/StiffnessCouplings.h"
#include "springs/VolumeForceField.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kBulk_Pa = 1e5;  // the bundled scene's volume term

/// The paper's strip, one cell across its thickness, in the tensile test's grips.
class SmallStrainCalibration : public ::testing::Test {
 protected:
  SmallStrainCalibration() {
    m_mesh = buildSpringMesh(makeTensileSpecimenMesh(m_specimen), 1000.0);
    m_grips.isFixed =
        tensileGripDofs(m_mesh.restPositions_m, m_specimen.size_m, m_grips.movingNodes);
    m_grips.length_m = m_specimen.size_m.x();
    m_grips.section_m2 = m_specimen.size_m.y() * m_specimen.size_m.z();
  }

  /// The nonlinear network's stress over strain at a stretch of 1 + 1e-6, every V_e scaled by
  /// `scale`: a converged static solve of the full spring (and volume) forces, not the
  /// linearisation.
  double nonlinearModulus(double scale, double bulkModulus_Pa) const {
    constexpr double kStrain = 1e-6;
    TensileOptions options;
    options.isSoftening = false;
    options.volumeScale = scale;
    options.bulkModulus_Pa = bulkModulus_Pa;
    options.forceTolerance_N = 1e-14;
    const TensileExperiment experiment(m_liver.energy, m_liver.table, m_specimen);
    return experiment.run(options, {{1.0 + kStrain}, 2}).front().stress_Pa.back() / kStrain;
  }

  const test::LiverMaterial& m_liver = test::LiverMaterial::instance();
  const TensileSpecimen m_specimen{{0.055, 0.020, 0.005}, 1};
  const SpringForceLaw m_law{SpringLaw::Eesm, m_liver.table, m_liver.parameters, 0.0, false};
  const double m_target_Pa = 3.0 * m_liver.energy.initialShearModulus();
  SpringMesh m_mesh;
  UniaxialGrips m_grips;
};

TEST_F(SmallStrainCalibration, TheScaledNetworkHasTheContinuumsModulusUnderANonlinearPull) {
  for (const double bulk_Pa : {0.0, kBulk_Pa}) {
    const double scale = smallStrainStiffnessScale(m_mesh, m_law, bulk_Pa, m_grips, m_target_Pa);
    // A network of central springs is several times softer than the continuum it stands for.
    EXPECT_GT(scale, 3.0) << bulk_Pa;
    EXPECT_LT(scale, 10.0) << bulk_Pa;
    EXPECT_NEAR(nonlinearModulus(scale, bulk_Pa), m_target_Pa, 1e-4 * m_target_Pa) << bulk_Pa;
    EXPECT_GT(std::abs(nonlinearModulus(1.0, bulk_Pa) - m_target_Pa), 0.5 * m_target_Pa);
  }
}

TEST_F(SmallStrainCalibration, TheVolumeTermTakesPartOfTheStiffnessSoTheSpringsNeedLess) {
  const double springsAlone = smallStrainStiffnessScale(m_mesh, m_law, 0.0, m_grips, m_target_Pa);
  const double withVolume =
      smallStrainStiffnessScale(m_mesh, m_law, kBulk_Pa, m_grips, m_target_Pa);
  EXPECT_LT(withVolume, springsAlone);
  SpringMesh scaled = m_mesh;
  scaled.volume_m3 *= withVolume;
  EXPECT_NEAR(smallStrainModulus(scaled, m_law, kBulk_Pa, m_grips), m_target_Pa,
              1e-9 * m_target_Pa);
}

TEST_F(SmallStrainCalibration, WithoutTheVolumeTermTheModulusIsLinearInTheSpringsVolumes) {
  const double once = smallStrainModulus(m_mesh, m_law, 0.0, m_grips);
  SpringMesh doubled = m_mesh;
  doubled.volume_m3 *= 2.0;
  EXPECT_NEAR(smallStrainModulus(doubled, m_law, 0.0, m_grips), 2.0 * once, 1e-10 * once);
  // And in the law's slope at rest: the eesm law's modulus is that of a linear law (smm) whose
  // modulus is the table's slope at rest.
  const double slopeAtRest_Pa = m_law.evaluate(1.0, 1.0).slope;
  const SpringForceLaw linear(SpringLaw::Smm, m_liver.table, m_liver.parameters, slopeAtRest_Pa,
                              false);
  EXPECT_NEAR(smallStrainModulus(m_mesh, linear, 0.0, m_grips), once, 1e-10 * once);
}

TEST_F(SmallStrainCalibration, GripsThatLeaveTheSpecimenFreeToMoveAreRefused) {
  // Only the moving grip's x held: nothing holds the other end, and the strip slides freely.
  UniaxialGrips loose = m_grips;
  std::fill(loose.isFixed.begin(), loose.isFixed.end(), 0);
  for (const int node : loose.movingNodes) loose.isFixed[static_cast<std::size_t>(3 * node)] = 1;
  try {
    smallStrainModulus(m_mesh, m_law, 0.0, loose);
    FAIL() << "a free specimen was calibrated";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("free to move"), std::string::npos) << error.what();
  }
  UniaxialGrips tooFewFlags = m_grips;
  tooFewFlags.isFixed.pop_back();
  EXPECT_THROW(smallStrainModulus(m_mesh, m_law, 0.0, tooFewFlags), std::invalid_argument);
  EXPECT_THROW(smallStrainStiffnessScale(m_mesh, m_law, 0.0, m_grips, 0.0), std::invalid_argument);
}

TEST(StiffnessCouplings, ACubesSpringsAndWithItsVolumeCellEveryPairOfItsCorners) {
  const SpringMesh cube = buildSpringMesh(makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1}), 1000.0);
  const Eigen::Matrix2Xi springsOnly = stiffnessCouplings(cube, nullptr);
  EXPECT_EQ(springsOnly, cube.springs);
  const VolumeForceField volume(cube, kBulk_Pa);
  const Eigen::Matrix2Xi all = stiffnessCouplings(cube, &volume.cells());
  ASSERT_EQ(all.cols(), 8 * 7 / 2);
  EXPECT_EQ(all.leftCols(cube.springCount()), cube.springs);
  std::set<std::pair<int, int>> pairs;
  for (Eigen::Index p = 0; p < all.cols(); ++p) {
    EXPECT_NE(all(0, p), all(1, p));
    pairs.emplace(std::min(all(0, p), all(1, p)), std::max(all(0, p), all(1, p)));
  }
  EXPECT_EQ(pairs.size(), static_cast<std::size_t>(all.cols()));
}

}  // namespace
}  // namespace tissuesim
