// SPDX-License-Identifier: Apache-2.0
#pragma once
// What one force pass saw, per force field, for the instability report: the springs' stretch
// range, the volume term's volume ratios, the FEM tets' range.

#include <algorithm>

namespace tissuesim {

struct SpringFieldReport {
  int beyondRangeCount = 0;  ///< springs past the material's usable range (locking barrier)
  int collapsedCount = 0;    ///< springs of (near) zero length: no direction, no force
  double minStretch = 1.0;
  double maxStretch = 1.0;

  /// Adds another range's counts and widens the stretch range to its.
  void include(const SpringFieldReport& other) {
    beyondRangeCount += other.beyondRangeCount;
    collapsedCount += other.collapsedCount;
    minStretch = std::min(minStretch, other.minStretch);
    maxStretch = std::max(maxStretch, other.maxStretch);
  }
};

struct VolumeFieldReport {
  int invertedTetCount = 0;  ///< tets with J <= 0
  /// Deformed over rest volume: the volume term's cells' (VolumeCells.h) from its pass, each
  /// tet's from VolumeForceField::inspect().
  double minVolumeRatio = 1.0;
  double maxVolumeRatio = 1.0;

  void include(const VolumeFieldReport& other) {
    invertedTetCount += other.invertedTetCount;
    minVolumeRatio = std::min(minVolumeRatio, other.minVolumeRatio);
    maxVolumeRatio = std::max(maxVolumeRatio, other.maxVolumeRatio);
  }
};

struct TetFieldReport {
  int beyondRangeCount = 0;  ///< tets past the material's usable range (continued linearly)
  int invertedCount = 0;     ///< tets with J <= 0 (no isochoric force)

  void include(const TetFieldReport& other) {
    beyondRangeCount += other.beyondRangeCount;
    invertedCount += other.invertedCount;
  }
};

/// A pass over every field of a system: each fills its own part (the defaults where absent).
struct ForceReport {
  SpringFieldReport springs;
  VolumeFieldReport volume;
  TetFieldReport tets;
};

}  // namespace tissuesim
