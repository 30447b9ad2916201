// SPDX-License-Identifier: Apache-2.0
#pragma once
// A headless session stepped to its end: what `run` and `replay` share. Its report (JSON: the
// physics rate, the largest tool force, penetration and stretch, the volume ratios, CG's
// products a step, the events, the session's assessment) and the one-line summary on stdout;
// optionally a ParaView time series of the states.

#include <functional>
#include <string>

#include "app/SceneSession.h"
#include "sim/SessionRecording.h"

namespace tissuesim::app {

struct SessionOutputs {
  std::string sceneLabel;  ///< the report's "scene"
  std::string reportPath;  ///< empty: none written
  std::string exportFolder;
  double exportEvery_s = 0.02;
  /// Called before step n (0-based) and after it: a replay's changes, its snapshot.
  std::function<void(long)> beforeStep;
  std::function<void(long)> afterStep;
};

/// Applies the recording's changes that take effect before `step` (the events from `next` on;
/// `next` is left at the first later one): a replay's inputs, as the live session saw them.
void applyRecordedChanges(const SessionRecording& recording, std::size_t& next, long step,
                          SceneSession& session);

/// Steps `session` `steps` times, timing the physics alone, and writes what `outputs` asks.
/// @throws CommandError on a bad export setting or an unwritable output.
void runSessionSteps(SceneSession& session, long steps, const SessionOutputs& outputs);

}  // namespace tissuesim::app
