// SPDX-License-Identifier: Apache-2.0
#include "sim/RandomSession.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "mesh/TriangleSurface.h"

namespace tissuesim {
namespace {

constexpr double kTransitSpeed_m_s = 0.5;

/// Against gravity; +y (the scenes' up) in a weightless scene.
Eigen::Vector3d upwardOf(const Simulation& simulation) {
  const Eigen::Vector3d& gravity = simulation.scene().gravity_m_s2;
  return gravity.squaredNorm() > 0.0 ? Eigen::Vector3d(-gravity.normalized())
                                     : Eigen::Vector3d::UnitY();
}

/// Vertices of the drawn surface (as settled) facing up, away from the held nodes: where a
/// trainee pokes. Falls back to the tet mesh's nodes when the scene draws no surface.
std::vector<Eigen::Vector3d> upperSurfacePoints(const Simulation& simulation) {
  const SceneGeometry& geometry = simulation.geometry();
  const Eigen::Matrix3Xd& x = simulation.state().x;
  std::vector<Eigen::Vector3d> points;
  Eigen::Matrix3Xd vertices;
  Eigen::Matrix3Xd normals;
  if (geometry.surface && geometry.embedding) {
    TriangleSurface drawn = *geometry.surface;
    geometry.embedding->apply(x, drawn.vertices_m);
    vertices = drawn.vertices_m;
    normals = vertexNormals(drawn);
  } else {
    vertices = x;
    normals = Eigen::Matrix3Xd::Zero(3, x.cols());
    normals.row(1).setOnes();  // every node a candidate; the fixed ones are left out below
  }
  const Eigen::Vector3d upward = upwardOf(simulation);
  const std::vector<int>& fixed = geometry.fixedNodes;
  for (Eigen::Index v = 0; v < vertices.cols(); ++v) {
    if (normals.col(v).dot(upward) < 0.5) continue;
    const Eigen::Vector3d p = vertices.col(v);
    // Away from the hold: no held node within 2 cm.
    const bool nearHold = std::any_of(fixed.begin(), fixed.end(), [&](int node) {
      return (x.col(node) - p).squaredNorm() < 0.02 * 0.02;
    });
    if (!nearHold) points.push_back(p);
  }
  return points;
}

}  // namespace

InstrumentScript randomSession(const Simulation& simulation, double duration_s,
                               std::uint64_t seed) {
  if (!simulation.scene().instrument)
    throw std::invalid_argument("the scene has no instrument to poke with");
  const std::vector<Eigen::Vector3d> targets = upperSurfacePoints(simulation);
  if (targets.empty())
    throw std::invalid_argument("the scene has no upper surface away from its hold to poke");
  const Eigen::Vector3d upward = upwardOf(simulation);
  double top = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : targets) top = std::max(top, p.dot(upward));
  const double transitHeight = top + 0.05;

  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, targets.size() - 1);
  const auto above = [&](const Eigen::Vector3d& p) {  // p raised to the transit height
    return Eigen::Vector3d(p + (transitHeight - p.dot(upward)) * upward);
  };

  const InstrumentPose start{simulation.scene().instrument->tipStart_m,
                             simulation.scene().instrument->direction};
  std::vector<InstrumentScript::Keyframe> keyframes{{0.0, start}};
  double t = 0.0;
  const auto add = [&](double dt, const Eigen::Vector3d& tip, const Eigen::Vector3d& direction,
                       bool isGrasping) {
    t += std::max(dt, 1e-3);
    keyframes.push_back({t, {tip, direction, isGrasping}});
  };
  // Moves through the air at 0.5 m/s, and no quicker than in 0.1 s.
  const auto travel = [&](const Eigen::Vector3d& tip, const Eigen::Vector3d& direction) {
    const double distance_m = (tip - keyframes.back().pose.tip_m).norm();
    add(std::max(0.1, distance_m / kTransitSpeed_m_s), tip, direction, false);
  };
  travel(above(start.tip_m), start.direction);
  int cycle = 0;
  while (t < duration_s) {
    const Eigen::Vector3d target = targets[pick(random)];
    // A shaft tilted up to 30 degrees off the downward vertical, about a random horizontal axis.
    const double tilt =
        std::acos(1.0 - unit(random) * (1.0 - std::cos(30.0 * std::numbers::pi / 180.0)));
    const double azimuth = 2.0 * std::numbers::pi * unit(random);
    const Eigen::Vector3d side = upward.unitOrthogonal();
    const Eigen::Vector3d axis = Eigen::AngleAxisd(azimuth, upward) * side;  // horizontal
    const Eigen::Vector3d direction = Eigen::AngleAxisd(tilt, axis) * (-upward);
    const double depth_m = 0.05 * unit(random);
    const double speed_m_s = 0.02 * std::pow(75.0, unit(random));  // 2 cm/s to 1.5 m/s, log-even
    const Eigen::Vector3d approach = target - 0.01 * direction;
    const Eigen::Vector3d deepest = target + depth_m * direction;
    const double pressTime_s = (0.01 + depth_m) / speed_m_s;

    add(0.1, above(approach), direction, false);  // over the target
    add(0.1, approach, direction, false);         // down to 1 cm above it
    add(pressTime_s, deepest, direction, false);  // in
    if (cycle % 3 == 2) {                         // grasp, lift 1 cm, release
      add(0.05, deepest, direction, true);
      add(0.3, deepest + 0.01 * upward, direction, true);
      add(0.05, deepest + 0.01 * upward, direction, false);
    }
    add(pressTime_s, approach, direction, false);                // out
    add(0.1, above(approach), direction, false);                 // up clear of the organ
    add(0.5 * unit(random), above(approach), direction, false);  // rest
    ++cycle;
  }
  return InstrumentScript(std::move(keyframes));
}

}  // namespace tissuesim
