// SPDX-License-Identifier: Apache-2.0
// The recording file: what is written is read back to the bit; a recording cut short, a line
// that is not JSON, a file that is not a recording, an event past the end and a scene file
// changed since are each refused with one line naming the file.

#include "sim/SessionRecording.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "support/TestTissues.h"

namespace tissuesim {
namespace {

const std::filesystem::path kScene = std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json";

SessionRecording sample() {
  SessionRecording recording;
  recording.scenePath = kScene;
  recording.files = sceneFingerprints(kScene);
  recording.isLive = true;
  RecordedEvent pose;
  pose.step = 3;
  pose.pose = InstrumentPose{{0.1, 0.2 / 3.0, -1e-17}, Eigen::Vector3d(1, 2, 3).normalized(), true};
  RecordedEvent tissue;
  tissue.step = 7;
  tissue.tissue = test::porcineLiver();
  tissue.tissue->mu_Pa *= 1.0 + 1e-15;  // a last bit that must survive
  RecordedEvent changes;
  changes.step = 7;
  changes.isReset = true;
  changes.softening = false;
  changes.gravity_m_s2 = Eigen::Vector3d(0.0, -9.81, 1.0 / 3.0);
  RecordedEvent refined;
  refined.step = 9;
  refined.isRefinedTowardsTool = true;
  recording.events = {pose, tissue, changes, refined};
  recording.steps = 12;
  return recording;
}

std::filesystem::path temporary(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("tissuesim-recording-test-" + name);
}

std::string textOf(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

std::string refusal(const std::filesystem::path& path) {
  try {
    const SessionRecording recording = readRecording(path);
    checkFingerprints(recording, path.string());
  } catch (const RecordingError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(path.string(), 0), 0u) << message;
    return message;
  }
  ADD_FAILURE() << path << " was accepted";
  return "";
}

TEST(SessionRecording, WhatIsWrittenIsReadBackToTheBit) {
  const SessionRecording written = sample();
  const std::filesystem::path path = temporary("round-trip.jsonl");
  writeRecording(path, written);
  const SessionRecording read = readRecording(path);
  EXPECT_EQ(read.scenePath, std::filesystem::absolute(kScene).lexically_normal());
  ASSERT_EQ(read.files.size(), 4u);  // scene, tissue, surface, tet mesh
  EXPECT_EQ(read.files[0].hash, written.files[0].hash);
  EXPECT_TRUE(read.isLive);
  EXPECT_EQ(read.steps, 12);
  ASSERT_EQ(read.events.size(), 4u);
  EXPECT_EQ(read.events[0].step, 3);
  EXPECT_EQ(read.events[0].pose->tip_m, written.events[0].pose->tip_m);
  EXPECT_EQ(read.events[0].pose->direction, written.events[0].pose->direction);
  EXPECT_TRUE(read.events[0].pose->isGrasping);
  EXPECT_EQ(read.events[1].tissue->mu_Pa, written.events[1].tissue->mu_Pa);
  EXPECT_EQ(read.events[1].tissue->name, written.events[1].tissue->name);
  EXPECT_EQ(read.events[1].tissue->softeningC_Pa, written.events[1].tissue->softeningC_Pa);
  EXPECT_TRUE(read.events[2].isReset);
  EXPECT_EQ(*read.events[2].softening, false);
  EXPECT_EQ(*read.events[2].gravity_m_s2, *written.events[2].gravity_m_s2);
  EXPECT_FALSE(read.events[2].isRefinedTowardsTool);
  EXPECT_EQ(read.events[3].step, 9);
  EXPECT_TRUE(read.events[3].isRefinedTowardsTool);
  checkFingerprints(read, path.string());  // the bundled files are as they were
  std::filesystem::remove(path);
}

TEST(SessionRecording, ARecordingCutShortIsRefused) {
  const std::filesystem::path path = temporary("cut.jsonl");
  writeRecording(path, sample());
  std::string text = textOf(path);
  text.erase(text.rfind("{\"end_steps\""));  // the end line lost, as when a save is cut off
  writeText(path, text);
  EXPECT_NE(refusal(path).find("cut short after line 5: no end line"), std::string::npos);
  writeText(path, text.substr(0, text.size() / 2));  // cut in the middle of a line
  EXPECT_NE(refusal(path).find("is not valid JSON"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(SessionRecording, CorruptLinesAndForeignFilesAreRefused) {
  const std::filesystem::path path = temporary("corrupt.jsonl");
  writeRecording(path, sample());
  const std::string text = textOf(path);
  const std::size_t second = text.find('\n') + 1;
  writeText(path,
            text.substr(0, second) + "{\"step\": 4, \"pose\": [1, 2]}\n" + text.substr(second));
  EXPECT_NE(refusal(path).find("line 2 field 'pose' must be [tip x"), std::string::npos);
  writeText(path,
            text.substr(0, second) + "{\"step\": 40, \"reset\": true}\n" + "{\"end_steps\": 12}\n");
  EXPECT_NE(refusal(path).find("an event at step 40 lies past the end (12 steps)"),
            std::string::npos);
  writeText(path,
            text.substr(0, second) + "{\"step\": 4, \"teleport\": true}\n" + text.substr(second));
  EXPECT_NE(refusal(path).find("line 2 has none of pose, reset"), std::string::npos);
  writeText(path, text.substr(0, second) + "{\"step\": 4, \"refined_towards_tool\": 1}\n" +
                      text.substr(second));
  EXPECT_NE(refusal(path).find("line 2 field 'refined_towards_tool' must be true"),
            std::string::npos);
  writeText(path, "{\"tissue\": \"../tissues/porcine-liver.json\"}\n");
  EXPECT_NE(refusal(path).find("not a TissueSim recording"), std::string::npos);
  writeText(path, "");
  EXPECT_NE(refusal(path).find("the recording is empty"), std::string::npos);
  std::filesystem::remove(path);
  EXPECT_NE(refusal(path).find("cannot open the recording"), std::string::npos);
}

TEST(SessionRecording, AChangedSceneFileIsRefused) {
  SessionRecording recording = sample();
  recording.files[1].hash ^= 1;  // as if the tissue file had been edited since
  const std::filesystem::path path = temporary("changed.jsonl");
  writeRecording(path, recording);
  EXPECT_NE(refusal(path).find("porcine-liver.json has changed since it was recorded"),
            std::string::npos);
  std::filesystem::remove(path);
}

TEST(SessionRecording, TheRecorderKeepsOnlyNewPosesAndEveryChange) {
  SessionRecorder recorder(kScene);
  const InstrumentPose a{{0.0, 0.1, 0.0}, -Eigen::Vector3d::UnitY(), false};
  InstrumentPose b = a;
  b.isGrasping = true;
  recorder.notePose(0, a);
  recorder.notePose(1, a);  // unchanged: not kept
  recorder.notePose(2, b);
  RecordedEvent reset;
  reset.step = 3;
  reset.isReset = true;
  recorder.noteChange(reset);
  recorder.notePose(3, b);  // unchanged by the reset: not kept
  const SessionRecording recording = recorder.recording(5);
  ASSERT_EQ(recording.events.size(), 3u);
  EXPECT_EQ(recording.events[0].step, 0);
  EXPECT_EQ(recording.events[1].step, 2);
  EXPECT_TRUE(recording.events[1].pose->isGrasping);
  EXPECT_TRUE(recording.events[2].isReset);
  EXPECT_EQ(recording.steps, 5);
}

}  // namespace
}  // namespace tissuesim
