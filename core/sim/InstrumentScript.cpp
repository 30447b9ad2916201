// SPDX-License-Identifier: Apache-2.0
#include "sim/InstrumentScript.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace tissuesim {

InstrumentScript::InstrumentScript(std::vector<Keyframe> keyframes)
    : m_keyframes(std::move(keyframes)) {
  if (m_keyframes.empty())
    throw std::invalid_argument("an instrument script needs at least one pose");
  for (std::size_t i = 1; i < m_keyframes.size(); ++i) {
    if (!(m_keyframes[i].time_s > m_keyframes[i - 1].time_s)) {
      throw std::invalid_argument("instrument script: pose " + std::to_string(i) +
                                  "'s time must exceed the previous one's");
    }
  }
}

InstrumentPose InstrumentScript::poseAt(double time_s) const {
  if (time_s <= m_keyframes.front().time_s) return m_keyframes.front().pose;
  if (time_s >= m_keyframes.back().time_s) return m_keyframes.back().pose;
  const auto next = std::upper_bound(m_keyframes.begin(), m_keyframes.end(), time_s,
                                     [](double t, const Keyframe& k) { return t < k.time_s; });
  const Keyframe& b = *next;
  const Keyframe& a = *(next - 1);
  const double s = (time_s - a.time_s) / (b.time_s - a.time_s);
  InstrumentPose pose;
  pose.tip_m = (1.0 - s) * a.pose.tip_m + s * b.pose.tip_m;
  pose.direction = ((1.0 - s) * a.pose.direction + s * b.pose.direction).normalized();
  pose.isGrasping = a.pose.isGrasping;  // the jaws switch at keyframes, not gradually
  return pose;
}

InstrumentScript InstrumentScript::poke(const InstrumentPose& start, double depth_m,
                                        double pressTime_s) {
  InstrumentPose deepest = start;
  deepest.tip_m += depth_m * start.direction;
  return InstrumentScript({{0.0, start}, {pressTime_s, deepest}, {2.0 * pressTime_s, start}});
}

InstrumentScript InstrumentScript::load(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(name + ": cannot open the instrument script");
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(name + ": not valid JSON; expected {\"poses\": [...]}");
  }
  if (!root.is_object() || !root.contains("poses") || !root["poses"].is_array() ||
      root["poses"].empty()) {
    throw std::invalid_argument(name + ": expected an object with a non-empty array 'poses'");
  }
  std::vector<Keyframe> keyframes;
  const auto vector = [&](const nlohmann::json& pose, const char* key, std::size_t index) {
    if (!pose.contains(key) || !pose[key].is_array() || pose[key].size() != 3) {
      throw std::invalid_argument(name + ": pose " + std::to_string(index) + ": '" + key +
                                  "' must be three numbers");
    }
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      if (!pose[key][static_cast<std::size_t>(i)].is_number()) {
        throw std::invalid_argument(name + ": pose " + std::to_string(index) + ": '" + key +
                                    "' must be three numbers");
      }
      v[i] = pose[key][static_cast<std::size_t>(i)].get<double>();
    }
    return v;
  };
  for (std::size_t i = 0; i < root["poses"].size(); ++i) {
    const nlohmann::json& pose = root["poses"][i];
    if (!pose.is_object() || !pose.contains("time_s") || !pose["time_s"].is_number()) {
      throw std::invalid_argument(name + ": pose " + std::to_string(i) +
                                  ": 'time_s' must be a number");
    }
    InstrumentPose p;
    p.tip_m = vector(pose, "tip_m", i);
    p.direction =
        pose.contains("direction") ? vector(pose, "direction", i) : Eigen::Vector3d(0, 0, -1);
    if (p.direction.norm() < 1e-9)
      throw std::invalid_argument(name + ": pose " + std::to_string(i) + ": zero direction");
    p.direction.normalize();
    if (pose.contains("grasp")) {
      if (!pose["grasp"].is_boolean())
        throw std::invalid_argument(name + ": pose " + std::to_string(i) +
                                    ": 'grasp' must be true or false");
      p.isGrasping = pose["grasp"].get<bool>();
    }
    keyframes.push_back({pose["time_s"].get<double>(), p});
  }
  try {
    return InstrumentScript(std::move(keyframes));
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(name + ": " + error.what());
  }
}

}  // namespace tissuesim
