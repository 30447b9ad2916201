// SPDX-License-Identifier: Apache-2.0
#pragma once
// A recorded session: what drove a scene, enough to step it again to the same bits (the engine
// is deterministic: no clocks, no randomness inside). Not the states: only the inputs.
//
// - A scripted session (`tissuesim run`): the script's keyframes and the step count.
// - A live session (the window): each new input pose (the target the tool's proxy tracks, the
//   grasper's jaws with it) at the physics step that first saw it, and the changes made
//   between steps: reset, softening, gravity, a new tissue, the body made again where the tool
//   aims.
//
// Steps are counted as the instrument source's calls (one a physics step, failed steps
// included), from the start of the session; an event at step k takes effect before step k.
// The files the scene reads are fingerprinted (FNV-1a, 64 bits), so a replay refuses a scene,
// tissue or mesh that has changed since.
//
// The file is JSON Lines: a header, one line an event, and an end line with the step count,
// written last, so a recording cut short is told from a finished one. A live session writes a
// line for each mouse move the physics saw, not one a step, so an hour of use stays small.
//
// Errors are RecordingError, one line naming the file, the line and what was expected.

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "material/TissueParameters.h"
#include "sim/InstrumentScript.h"

namespace tissuesim {

class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A change between physics steps: one of its optional fields set.
struct RecordedEvent {
  long step = 0;  ///< takes effect before this step (0-based)
  std::optional<InstrumentPose> pose;
  bool isReset = false;
  std::optional<bool> softening;
  std::optional<Eigen::Vector3d> gravity_m_s2;
  std::optional<TissueParameters> tissue;
  /// The body made again where the tool aims (Simulation::refineTowardsTool).
  bool isRefinedTowardsTool = false;
};

struct FileFingerprint {
  std::filesystem::path path;
  std::uint64_t hash = 0;
};

struct SessionRecording {
  std::filesystem::path scenePath;
  std::vector<FileFingerprint> files;  ///< the scene file and every file it names
  bool isLive = false;
  std::vector<InstrumentScript::Keyframe> script;  ///< scripted: empty without an instrument
  std::vector<RecordedEvent> events;               ///< live: in step order
  long steps = 0;
};

/// FNV-1a (64 bits) of a file's bytes. @throws RecordingError when it cannot be read.
std::uint64_t fileHash(const std::filesystem::path& path);

/// The scene file and the files it names (tissue, surface, tet mesh), fingerprinted now.
std::vector<FileFingerprint> sceneFingerprints(const std::filesystem::path& scenePath);

/// Throws RecordingError (naming `recordingPath`) if a fingerprinted file is missing or changed.
void checkFingerprints(const SessionRecording& recording, const std::string& recordingPath);

void writeRecording(const std::filesystem::path& path, const SessionRecording& recording);
/// @throws RecordingError: unreadable, not a recording, a bad line, or cut short.
SessionRecording readRecording(const std::filesystem::path& path);

/// Collects a live session's events from the physics thread (poses) and the window's (changes
/// made between steps, the physics paused), in step order. Poses are kept compact, with room
/// for some minutes of continuous mouse moves reserved; past that the list grows, once in a
/// while, on the physics thread (one late step, which the real-time loop makes up).
class SessionRecorder {
 public:
  /// @param scenePath the scene the session runs (its files are fingerprinted now).
  explicit SessionRecorder(const std::filesystem::path& scenePath);

  /// Physics side: the pose the source sees at `step`; recorded when it differs from the last.
  void notePose(long step, const InstrumentPose& pose);
  /// Window side, between steps: a change taking effect before `step`.
  void noteChange(RecordedEvent event);
  /// What was recorded, `steps` steps taken so far.
  SessionRecording recording(long steps) const;

 private:
  struct PoseRecord {
    long step;
    InstrumentPose pose;
  };
  mutable std::mutex m_mutex;
  SessionRecording m_recording;  ///< the header and the changes
  std::vector<PoseRecord> m_poses;
  std::optional<InstrumentPose> m_lastPose;
};

}  // namespace tissuesim
