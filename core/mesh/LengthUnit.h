#pragma once
// The length unit of a mesh file that does not say (STL, OBJ, Gmsh: none of them carries units):
// the one of metres, centimetres and millimetres that makes the mesh's size nearest an organ's.
// Medical exports are mostly in millimetres, CAD and graphics ones in anything; an organ is
// 5 to 30 cm across, so the three candidates (a factor of 10 or 1000 apart) are rarely in doubt.

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

}  // namespace tissuesim
