// SPDX-License-Identifier: Apache-2.0
#pragma once
// The length unit of a mesh file that does not say (STL, OBJ, Gmsh: none of them carries units):
// the one of metres, centimetres and millimetres that makes the mesh's size nearest an organ's.
// Medical exports are mostly in millimetres, CAD and graphics ones in anything; an organ is
// 5 to 30 cm across, so the three candidates (a factor of 10 or 1000 apart) are rarely in doubt.

#include <optional>

#include <Eigen/Core>

namespace tissuesim {

struct LengthUnit {
  const char* name;  ///< "metres", "centimetres", "millimetres"
  const char* symbol;
  double metresPerUnit;
};

/// The size (bounding-box diagonal) taken as an organ's when guessing: 15 cm.
inline constexpr double kOrganDiagonal_m = 0.15;

/// Of m, cm and mm, the unit that puts `diagonalInFileUnits` (> 0) nearest kOrganDiagonal_m by
/// ratio.
LengthUnit guessLengthUnit(double diagonalInFileUnits);

/// A unit guessed for a file, and the file's size in its own units.
struct GuessedUnit {
  LengthUnit unit;
  double diagonalInFileUnits;
};

/// Positions read at 1 mm a unit (the smallest candidate, so that no file is refused as too
/// large before its unit is known) rescaled to the guessed unit. nullopt, and the positions
/// untouched, when they have no extent or no finite one (the readers refuse those).
/// @throws std::invalid_argument ("a node lies X m from the origin in <unit>, the unit its size
/// suggests; expected an organ within 100 m") when the rescaled mesh is no organ in any unit.
std::optional<GuessedUnit> rescaleFromMillimetres(Eigen::Matrix3Xd& positions_m);

}  // namespace tissuesim
