// SPDX-License-Identifier: Apache-2.0
#include "mesh/LengthUnit.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tissuesim {

LengthUnit guessLengthUnit(double diagonalInFileUnits) {
  constexpr std::array<LengthUnit, 3> kUnits = {LengthUnit{"metres", "m", 1.0},
                                                LengthUnit{"centimetres", "cm", 0.01},
                                                LengthUnit{"millimetres", "mm", 0.001}};
  LengthUnit best = kUnits[0];
  double bestDistance = INFINITY;
  for (const LengthUnit& unit : kUnits) {
    const double distance =
        std::abs(std::log(diagonalInFileUnits * unit.metresPerUnit / kOrganDiagonal_m));
    if (distance < bestDistance) {
      bestDistance = distance;
      best = unit;
    }
  }
  return best;
}

std::optional<GuessedUnit> rescaleFromMillimetres(Eigen::Matrix3Xd& positions_m) {
  if (positions_m.cols() == 0) return std::nullopt;
  const double diagonal =
      (positions_m.rowwise().maxCoeff() - positions_m.rowwise().minCoeff()).norm() / 0.001;
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) return std::nullopt;
  const LengthUnit unit = guessLengthUnit(diagonal);
  positions_m *= unit.metresPerUnit / 0.001;
  const double farthest = positions_m.cwiseAbs().maxCoeff();
  if (farthest > 100.0) {
    throw std::invalid_argument("a node lies " + std::to_string(farthest) +
                                " m from the origin in " + unit.name +
                                ", the unit its size suggests; expected an organ within 100 m");
  }
  return GuessedUnit{unit, diagonal};
}

}  // namespace tissuesim
