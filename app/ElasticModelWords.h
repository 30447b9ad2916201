// SPDX-License-Identifier: Apache-2.0
#pragma once
// How the window's status bar and `run` name what carries a scene's elasticity, after the count
// of its elements: "springs", "tets (FEM)", or with the strain per face or per node
// (effects.strain_cells) "tets (FEM, strain per face)", or "quadratic tets (FEM at its own rate)"
// for the reference's element updated beside the probe's contact.

#include <string>

#include "sim/SceneFile.h"

namespace tissuesim {

inline std::string elasticModelWords(const SceneDescription& scene) {
  if (scene.model == "springs") return "springs";
  if (scene.model == "fem-haptic-rate") return "quadratic tets (FEM at its own rate)";
  if (scene.strainCells == "faces") return "tets (FEM, strain per face)";
  if (scene.strainCells == "nodes") return "tets (FEM, strain per node)";
  return "tets (FEM)";
}

}  // namespace tissuesim
