// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the instrument is at time t: from a script (tests, demos: timed poses, linearly
// interpolated), from the mouse, or from a haptic device later. The engine only sees this
// interface.

#include <filesystem>
#include <vector>

#include "forces/ContactProvider.h"

namespace tissuesim {

class InstrumentSource {
 public:
  virtual ~InstrumentSource() = default;
  virtual InstrumentPose poseAt(double time_s) const = 0;
  /// Whether the source moves its tool by the tool's clearance from the organ: at bounded speed,
  /// slower near an organ whose model follows the probe only so fast (sim/ToolProxy.h). The
  /// physics then measures it and notes it (m; <= 0 in contact) before it asks for each next
  /// pose. A script moves as written.
  virtual bool takesClearance() const { return false; }
  virtual void noteClearance(double /*clearance_m*/) const {}
};

/// Timed poses; between them positions are interpolated linearly, directions normalised.
/// The default poke of `run` and `snapshot` when no script is given: 4 cm along the tool over
/// 1 s, then back.
inline constexpr double kDefaultPokeDepth_m = 0.04;
inline constexpr double kDefaultPokePressTime_s = 1.0;

class InstrumentScript final : public InstrumentSource {
 public:
  struct Keyframe {
    double time_s;
    InstrumentPose pose;
  };
  explicit InstrumentScript(std::vector<Keyframe> keyframes);
  InstrumentPose poseAt(double time_s) const override;
  double duration_s() const { return m_keyframes.back().time_s; }
  const std::vector<Keyframe>& keyframes() const { return m_keyframes; }

  /// A straight poke: from `start` along its direction by `depth_m` over `pressTime_s`, then back.
  static InstrumentScript poke(const InstrumentPose& start, double depth_m, double pressTime_s);

  /// JSON: {"poses": [{"time_s": 0, "tip_m": [x, y, z], "direction": [x, y, z]}, ...]}, times
  /// increasing. @throws std::invalid_argument naming the file and the pose.
  static InstrumentScript load(const std::filesystem::path& path);

 private:
  std::vector<Keyframe> m_keyframes;
};

}  // namespace tissuesim
