#include "mesh/LengthUnit.h"

#include <array>
#include <cmath>

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

}  // namespace tissuesim
