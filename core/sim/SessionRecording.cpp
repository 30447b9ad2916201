// SPDX-License-Identifier: Apache-2.0
#include "sim/SessionRecording.h"

#include <charconv>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/SceneFile.h"

namespace tissuesim {
namespace {

constexpr const char* kFormat = "tissuesim recording";
constexpr int kVersion = 1;
/// A day at 1 ms: past that a count is a corrupt file's, not a session's.
constexpr long kMostSteps = 86400L * 1000L;

using Json = nlohmann::json;

Json poseJson(const InstrumentPose& pose) {
  return Json::array({pose.tip_m.x(), pose.tip_m.y(), pose.tip_m.z(), pose.direction.x(),
                      pose.direction.y(), pose.direction.z(), pose.isGrasping ? 1 : 0});
}

/// Each value as written, bit for bit (nlohmann writes doubles to round trip).
Json tissueJson(const TissueParameters& p) {
  return Json{{"name", p.name},
              {"source", p.source},
              {"mu_pa", p.mu_Pa},
              {"chain_segments_n", p.chainSegmentsN},
              {"a1_pa", p.A1_Pa},
              {"a2_pa", p.A2_Pa},
              {"fibre_fraction", p.fibreFraction},
              {"softening_b", p.softeningB},
              {"softening_c_pa", p.softeningC_Pa},
              {"softening_exponent_n", p.softeningExponentN},
              {"spring_area_m2", p.springArea_m2},
              {"density_kg_m3", p.density_kg_m3},
              {"damage_stretch", p.damageStretch},
              {"inverse_langevin", p.inverseLangevin == InverseLangevin::Exact ? "exact" : "puso"}};
}

std::string hexOf(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

/// Reads one line's fields, each error naming the file and the line.
class LineReader {
 public:
  LineReader(std::string file, int line, const std::string& text)
      : m_file(std::move(file)), m_line(line) {
    try {
      m_json = Json::parse(text);
    } catch (const Json::parse_error&) {
      fail("is not valid JSON");
    }
    if (!m_json.is_object()) fail("is not a JSON object");
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw RecordingError(m_file + ": line " + std::to_string(m_line) + " " + what);
  }
  bool has(const char* key) const { return m_json.contains(key); }
  const Json& json() const { return m_json; }

  double number(const Json& value, const std::string& field) const {
    if (!value.is_number()) fail("field '" + field + "' must be a number");
    return value.get<double>();
  }
  long count(const char* key) const {
    const Json& value = m_json.at(key);
    if (!value.is_number_integer() || value.get<long>() < 0)
      fail(std::string("field '") + key + "' must be a whole number >= 0");
    return value.get<long>();
  }
  InstrumentPose pose(const Json& value, const std::string& field) const {
    if (!value.is_array() || value.size() != 7)
      fail("field '" + field + "' must be [tip x, y, z, direction x, y, z, grasping 0 or 1]");
    InstrumentPose pose;
    for (int i = 0; i < 3; ++i) {
      pose.tip_m(i) = number(value[static_cast<std::size_t>(i)], field);
      pose.direction(i) = number(value[static_cast<std::size_t>(3 + i)], field);
    }
    pose.isGrasping = number(value[6], field) != 0.0;
    if (!pose.tip_m.allFinite() || !(std::abs(pose.direction.norm() - 1.0) < 1e-6))
      fail("field '" + field + "' must have a finite tip and a unit direction");
    return pose;
  }
  TissueParameters tissue(const Json& value) const {
    const auto field = [&](const char* key) -> const Json& {
      if (!value.is_object() || !value.contains(key))
        fail(std::string("field 'tissue' lacks '") + key + "'");
      return value.at(key);
    };
    TissueParameters p;
    const auto text = [&](const char* key) {
      if (!field(key).is_string()) fail(std::string("field 'tissue.") + key + "' must be text");
      return field(key).get<std::string>();
    };
    p.name = text("name");
    p.source = text("source");
    p.mu_Pa = number(field("mu_pa"), "tissue.mu_pa");
    p.chainSegmentsN = number(field("chain_segments_n"), "tissue.chain_segments_n");
    p.A1_Pa = number(field("a1_pa"), "tissue.a1_pa");
    p.A2_Pa = number(field("a2_pa"), "tissue.a2_pa");
    p.fibreFraction = number(field("fibre_fraction"), "tissue.fibre_fraction");
    p.softeningB = number(field("softening_b"), "tissue.softening_b");
    p.softeningC_Pa = number(field("softening_c_pa"), "tissue.softening_c_pa");
    const double exponent = number(field("softening_exponent_n"), "tissue.softening_exponent_n");
    if (exponent != 1.0 && exponent != 2.0)
      fail("field 'tissue.softening_exponent_n' must be 1 or 2");
    p.softeningExponentN = static_cast<int>(exponent);
    p.springArea_m2 = number(field("spring_area_m2"), "tissue.spring_area_m2");
    p.density_kg_m3 = number(field("density_kg_m3"), "tissue.density_kg_m3");
    // Optional: recordings written before the assessment have none (the default then).
    if (value.contains("damage_stretch")) {
      p.damageStretch = number(field("damage_stretch"), "tissue.damage_stretch");
      if (!(p.damageStretch > 1.0)) fail("field 'tissue.damage_stretch' must be above 1");
    }
    p.inverseLangevin =
        text("inverse_langevin") == "exact" ? InverseLangevin::Exact : InverseLangevin::Puso;
    return p;
  }

 private:
  std::string m_file;
  int m_line;
  Json m_json;
};

}  // namespace

std::uint64_t fileHash(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RecordingError(path.string() + ": cannot be read");
  std::uint64_t hash = 14695981039346656037ULL;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      hash ^= static_cast<unsigned char>(buffer[i]);
      hash *= 1099511628211ULL;
    }
  }
  return hash;
}

std::vector<FileFingerprint> sceneFingerprints(const std::filesystem::path& scenePath) {
  const SceneDescription scene = loadSceneFile(scenePath);
  std::vector<std::filesystem::path> paths{scene.source, scene.tissue};
  if (scene.surface) paths.push_back(scene.surface->file);
  if (scene.tetMesh) paths.push_back(scene.tetMesh->file);
  std::vector<FileFingerprint> files;
  for (const std::filesystem::path& path : paths) {
    const std::filesystem::path absolute = std::filesystem::absolute(path).lexically_normal();
    files.push_back({absolute, fileHash(absolute)});
  }
  return files;
}

void checkFingerprints(const SessionRecording& recording, const std::string& recordingPath) {
  for (const FileFingerprint& file : recording.files) {
    std::uint64_t now = 0;
    try {
      now = fileHash(file.path);
    } catch (const RecordingError&) {
      throw RecordingError(recordingPath + ": the session's file " + file.path.string() +
                           " cannot be read");
    }
    if (now != file.hash) {
      throw RecordingError(recordingPath + ": the session's file " + file.path.string() +
                           " has changed since it was recorded; a replay would differ");
    }
  }
}

void writeRecording(const std::filesystem::path& path, const SessionRecording& recording) {
  std::ostringstream out;
  Json header{{"format", kFormat},
              {"version", kVersion},
              {"scene", std::filesystem::absolute(recording.scenePath).lexically_normal().string()},
              {"live", recording.isLive}};
  Json files = Json::array();
  for (const FileFingerprint& file : recording.files)
    files.push_back({{"path", file.path.string()}, {"fnv1a64", hexOf(file.hash)}});
  header["files"] = files;
  Json script = Json::array();
  for (const InstrumentScript::Keyframe& key : recording.script) {
    Json pose = poseJson(key.pose);
    pose.insert(pose.begin(), key.time_s);
    script.push_back(pose);
  }
  header["script"] = script;
  out << header.dump() << '\n';
  for (const RecordedEvent& event : recording.events) {
    Json line{{"step", event.step}};
    if (event.pose) line["pose"] = poseJson(*event.pose);
    if (event.isReset) line["reset"] = true;
    if (event.softening) line["softening"] = *event.softening;
    if (event.gravity_m_s2)
      line["gravity_m_s2"] = {event.gravity_m_s2->x(), event.gravity_m_s2->y(),
                              event.gravity_m_s2->z()};
    if (event.tissue) line["tissue"] = tissueJson(*event.tissue);
    if (event.isRefinedTowardsTool) line["refined_towards_tool"] = true;
    out << line.dump() << '\n';
  }
  out << Json{{"end_steps", recording.steps}}.dump() << '\n';
  std::ofstream file(path, std::ios::binary);
  file << out.str();
  if (!file) throw RecordingError(path.string() + ": cannot be written");
}

SessionRecording readRecording(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string name = path.string();
  if (!in) throw RecordingError(name + ": cannot open the recording");
  SessionRecording recording;
  std::string text;
  int line = 0;
  bool isEnded = false;
  while (std::getline(in, text)) {
    ++line;
    if (text.empty()) continue;
    if (isEnded)
      throw RecordingError(name + ": line " + std::to_string(line) + " follows the end line");
    if (line == 1 && !Json::accept(text)) {
      throw RecordingError(name +
                           ": not a TissueSim recording (its first line is not a JSON "
                           "header)");
    }
    const LineReader reader(name, line, text);
    const Json& json = reader.json();
    if (line == 1) {
      if (!json.contains("format") || json.at("format") != kFormat)
        throw RecordingError(name + ": not a TissueSim recording (line 1 has no \"format\": \"" +
                             kFormat + "\")");
      if (!json.contains("version") || json.at("version") != kVersion)
        reader.fail("has a version this program does not read (expected " +
                    std::to_string(kVersion) + ")");
      if (!json.contains("scene") || !json.at("scene").is_string())
        reader.fail("lacks the scene's path");
      recording.scenePath = json.at("scene").get<std::string>();
      if (json.contains("live") && !json.at("live").is_boolean())
        reader.fail("field 'live' must be true or false");
      recording.isLive = json.value("live", false);
      for (const Json& file : json.value("files", Json::array())) {
        if (!file.is_object() || !file.contains("path") || !file.contains("fnv1a64") ||
            !file.at("path").is_string() || !file.at("fnv1a64").is_string())
          reader.fail("has a file entry without 'path' and 'fnv1a64'");
        const std::string hex = file.at("fnv1a64").get<std::string>();
        std::uint64_t hash = 0;
        const auto [end, error] = std::from_chars(hex.data(), hex.data() + hex.size(), hash, 16);
        if (error != std::errc() || end != hex.data() + hex.size() || hex.empty())
          reader.fail("has a file fingerprint that is not 16 hexadecimal digits");
        recording.files.push_back({file.at("path").get<std::string>(), hash});
      }
      for (const Json& key : json.value("script", Json::array())) {
        if (!key.is_array() || key.size() != 8)
          reader.fail("has a script keyframe that is not 8 numbers");
        const Json pose(key.begin() + 1, key.end());
        recording.script.push_back({reader.number(key[0], "script"), reader.pose(pose, "script")});
      }
      continue;
    }
    if (json.contains("end_steps")) {
      recording.steps = reader.count("end_steps");
      if (recording.steps > kMostSteps)
        reader.fail("field 'end_steps' is more than a day of steps at 1 ms");
      isEnded = true;
      continue;
    }
    if (!json.contains("step")) reader.fail("lacks 'step'");
    RecordedEvent event;
    event.step = reader.count("step");
    if (!recording.events.empty() && event.step < recording.events.back().step)
      reader.fail("goes back in time (step " + std::to_string(event.step) + " after " +
                  std::to_string(recording.events.back().step) + ")");
    bool isKnown = false;
    if (json.contains("pose")) {
      event.pose = reader.pose(json.at("pose"), "pose");
      isKnown = true;
    }
    if (json.contains("reset")) {
      event.isReset = true;
      isKnown = true;
    }
    if (json.contains("softening")) {
      if (!json.at("softening").is_boolean())
        reader.fail("field 'softening' must be true or false");
      event.softening = json.at("softening").get<bool>();
      isKnown = true;
    }
    if (json.contains("gravity_m_s2")) {
      const Json& g = json.at("gravity_m_s2");
      if (!g.is_array() || g.size() != 3) reader.fail("field 'gravity_m_s2' must be three numbers");
      event.gravity_m_s2 =
          Eigen::Vector3d(reader.number(g[0], "gravity_m_s2"), reader.number(g[1], "gravity_m_s2"),
                          reader.number(g[2], "gravity_m_s2"));
      isKnown = true;
    }
    if (json.contains("tissue")) {
      event.tissue = reader.tissue(json.at("tissue"));
      isKnown = true;
    }
    if (json.contains("refined_towards_tool")) {
      if (json.at("refined_towards_tool") != true)
        reader.fail("field 'refined_towards_tool' must be true");
      event.isRefinedTowardsTool = true;
      isKnown = true;
    }
    if (!isKnown)
      reader.fail("has none of pose, reset, softening, gravity_m_s2, tissue, refined_towards_tool");
    recording.events.push_back(std::move(event));
  }
  if (line == 0) throw RecordingError(name + ": the recording is empty");
  if (!isEnded) {
    throw RecordingError(name + ": cut short after line " + std::to_string(line) +
                         ": no end line (the session was not saved to its end)");
  }
  if (!recording.events.empty() && recording.events.back().step > recording.steps)
    throw RecordingError(name + ": an event at step " +
                         std::to_string(recording.events.back().step) + " lies past the end (" +
                         std::to_string(recording.steps) + " steps)");
  return recording;
}

SessionRecorder::SessionRecorder(const std::filesystem::path& scenePath) {
  m_recording.scenePath = scenePath;
  m_recording.files = sceneFingerprints(scenePath);
  m_recording.isLive = true;
  m_poses.reserve(1 << 15);  // about nine minutes of mouse moves at 60 a second
}

void SessionRecorder::notePose(long step, const InstrumentPose& pose) {
  if (m_lastPose && m_lastPose->tip_m == pose.tip_m && m_lastPose->direction == pose.direction &&
      m_lastPose->isGrasping == pose.isGrasping) {
    return;
  }
  m_lastPose = pose;
  const std::lock_guard<std::mutex> lock(m_mutex);
  m_poses.push_back({step, pose});
}

void SessionRecorder::noteChange(RecordedEvent event) {
  const std::lock_guard<std::mutex> lock(m_mutex);
  m_recording.events.push_back(std::move(event));
}

SessionRecording SessionRecorder::recording(long steps) const {
  const std::lock_guard<std::mutex> lock(m_mutex);
  SessionRecording copy = m_recording;
  copy.steps = steps;
  // The changes and the poses merged by step (a change before a pose of the same step: both
  // take effect before it, and neither touches the other).
  copy.events.clear();
  std::size_t change = 0;
  for (const PoseRecord& pose : m_poses) {
    while (change < m_recording.events.size() && m_recording.events[change].step <= pose.step)
      copy.events.push_back(m_recording.events[change++]);
    RecordedEvent event;
    event.step = pose.step;
    event.pose = pose.pose;
    copy.events.push_back(std::move(event));
  }
  copy.events.insert(copy.events.end(),
                     m_recording.events.begin() + static_cast<std::ptrdiff_t>(change),
                     m_recording.events.end());
  return copy;
}

}  // namespace tissuesim
