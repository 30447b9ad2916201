// SPDX-License-Identifier: Apache-2.0
#include "analysis/IndentationHapticRate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "mesh/BlockMesher.h"
#include "mesh/TetRefinement.h"

namespace tissuesim {

TetMesh indentationBody(const IndentationSetup& setup, const IndentationBodyGrading& grading) {
  if (!(grading.coarsest_m > 0.0))
    throw std::invalid_argument("the block's body needs its coarsest cells above 0");
  const Eigen::Vector3d& size = setup.size_m;
  Eigen::Vector3i cells;
  for (int axis = 0; axis < 3; ++axis)
    cells[axis] = std::max(1, static_cast<int>(std::lround(size[axis] / grading.coarsest_m)));
  TetMeshGrading towardsProbe;
  towardsProbe.centre_m = Eigen::Vector3d(0.5 * size.x(), 0.5 * size.y(), size.z());
  towardsProbe.finest_m = grading.finest_m;
  towardsProbe.growth = grading.growth;
  towardsProbe.coarsest_m = grading.coarsest_m;
  return refineTetMesh(makeBlockMesh(size, cells), towardsProbe).mesh;
}

HapticRatePoke indentHapticRate(const StrainEnergy& energy, const IndentationSetup& setup,
                                const IndentationBodyGrading& grading, double bulkModulus_Pa,
                                double contactSpacing_m, const HapticRateSettings& settings) {
  if (!(contactSpacing_m >= 0.0))
    throw std::invalid_argument("the probe's contact points need a spacing of at least 0");
  const TetMesh block = indentationBody(setup, grading);
  const Eigen::Vector3d& size = setup.size_m;
  OrganPokeSetup poke;
  // Started well above the top face: the depths are below where the axis meets it.
  poke.tipStart_m = Eigen::Vector3d(0.5 * size.x(), 0.5 * size.y(), size.z() + 0.01);
  poke.direction = -Eigen::Vector3d::UnitZ();
  poke.probeRadius_m = setup.probeRadius_m;
  // The bottom face held, as the reference holds it.
  const double onPlane_m = 1e-9 * size.maxCoeff();
  poke.fixedBox_m =
      Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-onPlane_m),
                          Eigen::Vector3d(size.x() + onPlane_m, size.y() + onPlane_m, onPlane_m));
  poke.depths_m = setup.depths_m;
  poke.pressureStiffness_Pa_m = setup.pressureStiffness_Pa_m;
  poke.contactSpacing_m = contactSpacing_m;
  return pokeOrganHapticRate(energy, block, poke, bulkModulus_Pa, settings);
}

}  // namespace tissuesim
