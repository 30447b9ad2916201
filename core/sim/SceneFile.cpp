// SPDX-License-Identifier: Apache-2.0
#include "sim/SceneFile.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "springs/SpringForceLaw.h"

namespace tissuesim {
namespace {

using Json = nlohmann::json;

/// Reads one JSON object's fields with messages naming the file and the dotted field path.
class Fields {
 public:
  Fields(const Json& object, std::string path, const std::string& source,
         std::set<std::string> allowed)
      : m_object(object), m_path(std::move(path)), m_source(source) {
    if (!object.is_object()) fail(m_path.empty() ? "the scene" : m_path, "must be a JSON object");
    for (const auto& item : object.items()) {
      if (allowed.count(item.key()) == 0) {
        std::string list;
        for (const std::string& key : allowed) list += (list.empty() ? "" : ", ") + key;
        fail(name(item.key()), "is not a known field; allowed: " + list);
      }
    }
  }
  bool has(const char* key) const { return m_object.contains(key); }
  const Json& at(const char* key) const { return m_object.at(key); }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw SceneFileError(m_source + ": field '" + field + "' " + what);
  }
  std::string name(const std::string& key) const {
    return m_path.empty() ? key : m_path + "." + key;
  }

  const Json& require(const char* key) const {
    if (!has(key)) fail(name(key), "is missing");
    return at(key);
  }
  double number(const char* key, double fallback, double lower, bool isStrict,
                bool isRequired = false) const {
    if (!has(key)) {
      if (isRequired) fail(name(key), "is missing");
      return fallback;
    }
    const Json& value = at(key);
    if (!value.is_number())
      fail(name(key), "must be a number, found " + std::string(value.type_name()));
    const double x = value.get<double>();
    if (!std::isfinite(x) || (isStrict ? !(x > lower) : !(x >= lower))) {
      std::ostringstream bound;
      bound << (isStrict ? "> " : ">= ") << lower;
      fail(name(key),
           "= " + value.dump() + " is out of range; expected a finite number " + bound.str());
    }
    return x;
  }
  std::string string(const char* key, const std::string& fallback, bool isRequired = false) const {
    if (!has(key)) {
      if (isRequired) fail(name(key), "is missing");
      return fallback;
    }
    if (!at(key).is_string())
      fail(name(key), "must be a string, found " + std::string(at(key).type_name()));
    return at(key).get<std::string>();
  }
  bool boolean(const char* key, bool fallback) const {
    if (!has(key)) return fallback;
    if (!at(key).is_boolean()) fail(name(key), "must be true or false");
    return at(key).get<bool>();
  }
  Eigen::Vector3d vector(const char* key, const Eigen::Vector3d& fallback,
                         bool isRequired = false) const {
    if (!has(key)) {
      if (isRequired) fail(name(key), "is missing");
      return fallback;
    }
    const Json& value = at(key);
    if (!value.is_array() || value.size() != 3)
      fail(name(key), "must be an array of three numbers");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      if (!value[static_cast<std::size_t>(i)].is_number())
        fail(name(key), "must be an array of three numbers");
      v[i] = value[static_cast<std::size_t>(i)].get<double>();
    }
    if (!v.allFinite()) fail(name(key), "must hold finite numbers");
    return v;
  }

 private:
  const Json& m_object;
  std::string m_path;
  const std::string& m_source;
};

std::filesystem::path resolveFile(const Fields& fields, const char* key,
                                  const std::filesystem::path& folder) {
  const std::filesystem::path file = folder / fields.string(key, "", true);
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    fields.fail(fields.name(key),
                "names " + file.string() + ", which does not exist or is not a file");
  }
  return file;
}

SceneMeshSource meshSource(const Json& object, const std::string& path, const std::string& source,
                           const std::filesystem::path& folder, bool isSurface) {
  std::set<std::string> allowed = {"file", "metres_per_unit"};
  allowed.insert(isSurface ? "part" : "refine_towards_tool");
  const Fields fields(object, path, source, allowed);
  SceneMeshSource mesh;
  mesh.file = resolveFile(fields, "file", folder);
  mesh.metresPerUnit = fields.number("metres_per_unit", 0.0, 0.0, true);
  if (isSurface) mesh.part = fields.string("part", "");
  if (!isSurface && fields.has("refine_towards_tool")) {
    const std::string name = path + ".refine_towards_tool";
    const Fields refine(fields.at("refine_towards_tool"), name, source,
                        {"finest_mm", "growth", "coarsest_mm"});
    SceneTetRefinement refinement;
    refinement.finest_m = refine.number("finest_mm", 4.0, 0.0, true) / 1000.0;
    refinement.growth = refine.number("growth", refinement.growth, 0.0, false);
    refinement.coarsest_m = refine.number("coarsest_mm", 24.0, 0.0, true) / 1000.0;
    // A bound below a tenth of a millimetre would split an organ's mesh into millions of tets.
    if (refinement.finest_m < 1e-4) refine.fail(name + ".finest_mm", "must be at least 0.1");
    if (refinement.coarsest_m < refinement.finest_m)
      refine.fail(name + ".coarsest_mm", "must be at least finest_mm");
    mesh.refinement = refinement;
  }
  return mesh;
}

}  // namespace

SceneDescription loadSceneFile(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::ifstream in(path);
  std::error_code error;
  if (std::filesystem::is_directory(path, error) || !in) {
    throw SceneFileError(source + ": cannot open the scene file (missing or unreadable)");
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw SceneFileError(source +
                         ": the file is empty; expected a JSON object (see docs/scene-file.md)");
  }
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::exception& parseError) {
    std::string detail = parseError.what();
    if (const auto colon = detail.find("] "); colon != std::string::npos)
      detail = detail.substr(colon + 2);
    if (const auto lastRead = detail.find("; last read"); lastRead != std::string::npos)
      detail = detail.substr(0, lastRead);
    throw SceneFileError(source + ": not valid JSON (" + detail + ")");
  }
  const std::filesystem::path folder = path.parent_path();
  const Fields fields(
      root, "", source,
      {"name", "tissue", "surface", "tet_mesh", "generate_tet_mesh", "fixed_region", "gravity_m_s2",
       "tray", "instrument", "effects", "physics", "assessment", "notes"});
  SceneDescription scene;
  scene.source = path;
  scene.name = fields.string("name", path.stem().string());
  scene.tissue = resolveFile(fields, "tissue", folder);
  if (fields.has("surface"))
    scene.surface = meshSource(fields.at("surface"), "surface", source, folder, true);
  if (fields.has("tet_mesh"))
    scene.tetMesh = meshSource(fields.at("tet_mesh"), "tet_mesh", source, folder, false);
  if (fields.has("generate_tet_mesh")) {
    const Fields generate(fields.at("generate_tet_mesh"), "generate_tet_mesh", source,
                          {"target_springs"});
    scene.targetSprings = static_cast<int>(generate.number("target_springs", 0, 6, false, true));
    if (!scene.surface) fields.fail("generate_tet_mesh", "needs a 'surface' to mesh");
  }
  if (scene.tetMesh && scene.targetSprings > 0) {
    fields.fail("generate_tet_mesh", "and 'tet_mesh' are both given; name one");
  }
  if (!scene.tetMesh && scene.targetSprings == 0) {
    fields.fail("tet_mesh", "is missing (or give 'generate_tet_mesh' with a 'surface')");
  }
  if (scene.tetMesh && scene.tetMesh->refinement && !scene.surface) {
    fields.fail("tet_mesh.refine_towards_tool",
                "needs a 'surface': the refined boundary is moved onto it");
  }
  if (fields.has("fixed_region")) {
    const Fields fixed(fields.at("fixed_region"), "fixed_region", source,
                       {"box_min_m", "box_max_m", "nodes"});
    if (fixed.has("box_min_m") || fixed.has("box_max_m")) {
      const Eigen::Vector3d lower = fixed.vector("box_min_m", Eigen::Vector3d::Zero(), true);
      const Eigen::Vector3d upper = fixed.vector("box_max_m", Eigen::Vector3d::Zero(), true);
      if ((lower.array() >= upper.array()).any())
        fixed.fail("fixed_region.box_max_m", "must exceed box_min_m on every axis");
      scene.fixed.box_m = Eigen::AlignedBox3d(lower, upper);
    }
    if (fixed.has("nodes")) {
      const Json& nodes = fixed.at("nodes");
      if (!nodes.is_array()) fixed.fail("fixed_region.nodes", "must be an array of node indices");
      for (const Json& node : nodes) {
        if (!node.is_number_integer() || node.get<long long>() < 0)
          fixed.fail("fixed_region.nodes", "must hold non-negative integers");
        scene.fixed.nodes.push_back(node.get<int>());
      }
    }
  }
  scene.gravity_m_s2 = fields.vector("gravity_m_s2", Eigen::Vector3d::Zero());
  if (fields.has("tray")) {
    const Fields trayFields(fields.at("tray"), "tray", source,
                            {"up", "height_m", "stiffness_pa_per_m", "friction"});
    SceneTray tray;
    const Eigen::Vector3d up = trayFields.vector("up", Eigen::Vector3d::UnitY());
    if (up.norm() < 1e-9) trayFields.fail("tray.up", "must not be the zero vector");
    tray.up = up.normalized();
    tray.height_m =
        trayFields.number("height_m", 0.0, -std::numeric_limits<double>::max(), false, true);
    tray.stiffness_Pa_per_m = trayFields.number("stiffness_pa_per_m", 1e7, 0.0, true);
    tray.friction = trayFields.number("friction", 0.0, 0.0, false);
    scene.tray = tray;
  }
  if (fields.has("instrument")) {
    const Fields tool(fields.at("instrument"), "instrument", source,
                      {"shaft_radius_mm", "shaft_length_mm", "tip_start_m", "direction"});
    SceneInstrument instrument;
    instrument.shaftRadius_m = tool.number("shaft_radius_mm", 2.5, 0.0, true) / 1000.0;
    instrument.shaftLength_m = tool.number("shaft_length_mm", 300.0, 0.0, true) / 1000.0;
    instrument.tipStart_m = tool.vector("tip_start_m", Eigen::Vector3d::Zero(), true);
    const Eigen::Vector3d direction = tool.vector("direction", -Eigen::Vector3d::UnitZ());
    if (direction.norm() < 1e-9) tool.fail("instrument.direction", "must not be the zero vector");
    instrument.direction = direction.normalized();
    scene.instrument = instrument;
  }
  if (scene.tetMesh && scene.tetMesh->refinement && !scene.instrument) {
    fields.fail("tet_mesh.refine_towards_tool",
                "needs an 'instrument': the mesh is refined where its axis meets the organ");
  }
  if (fields.has("effects")) {
    const Fields effects(fields.at("effects"), "effects", source,
                         {"model", "softening", "volume_term_kpa", "volume_cells", "strain_cells",
                          "spring_law", "stiffness_scale"});
    scene.model = effects.string("model", "springs");
    if (scene.model != "springs" && scene.model != "fem" && scene.model != "fem-haptic-rate") {
      effects.fail("effects.model",
                   "= \"" + scene.model + "\"; expected springs, fem or fem-haptic-rate");
    }
    const bool isFem = scene.model != "springs";
    // The FEM on the lattice's tets carries no stress softening; the springs and the FEM at its
    // own rate (per material point) do.
    const bool canSoften = scene.model != "fem";
    scene.isSoftening = effects.boolean("softening", canSoften);
    if (!canSoften && scene.isSoftening) {
      effects.fail("effects.softening",
                   "must be false with model " + scene.model + ", which has no softening");
    }
    scene.bulkModulus_Pa = effects.number("volume_term_kpa", 0.0, 0.0, false) * 1000.0;
    if (isFem && !(scene.bulkModulus_Pa > 0.0)) {
      effects.fail("effects.volume_term_kpa",
                   "must be > 0 with model " + scene.model + ": it is the FEM's volumetric part");
    }
    scene.volumeCells = effects.string("volume_cells", "cubes");
    if (scene.volumeCells != "cubes" && scene.volumeCells != "nodes")
      effects.fail("effects.volume_cells",
                   "= \"" + scene.volumeCells + "\"; expected cubes or nodes");
    if (scene.volumeCells == "nodes" && !(scene.bulkModulus_Pa > 0.0))
      effects.fail("effects.volume_cells", "= \"nodes\" needs volume_term_kpa above 0");
    scene.strainCells = effects.string("strain_cells", "tets");
    if (scene.strainCells != "tets" && scene.strainCells != "faces" && scene.strainCells != "nodes")
      effects.fail("effects.strain_cells",
                   "= \"" + scene.strainCells + "\"; expected tets, faces or nodes");
    if (scene.strainCells != "tets" && scene.model != "fem")
      effects.fail("effects.strain_cells", "= \"" + scene.strainCells + "\" is for model fem");
    scene.springLaw = effects.string("spring_law", "eesm");
    scene.stiffnessScale = effects.number("stiffness_scale", 0.0, 0.0, false);
    if (!springLawNamed(scene.springLaw)) {
      effects.fail("effects.spring_law",
                   "= \"" + scene.springLaw + "\"; expected eesm, eesm-paper or smm");
    }
  }
  if (fields.has("physics")) {
    const Fields physics(fields.at("physics"), "physics", source,
                         {"time_step_ms", "integrator", "mass_damping_per_s", "newton_iterations",
                          "cg_tolerance", "threads", "fem_update_latency_ms"});
    scene.timeStep_s = physics.number("time_step_ms", 1.0, 0.0, true) / 1000.0;
    scene.integrator = physics.string("integrator", "implicit");
    if (scene.integrator != "explicit" && scene.integrator != "implicit" &&
        scene.integrator != "quasi-newton") {
      physics.fail("physics.integrator",
                   "= \"" + scene.integrator + "\"; expected explicit, implicit or quasi-newton");
    }
    scene.massDamping_1_s = physics.number("mass_damping_per_s", 0.0, 0.0, false);
    scene.newtonIterations = static_cast<int>(physics.number("newton_iterations", 2, 1, false));
    scene.linearTolerance = physics.number("cg_tolerance", 1e-6, 0.0, true);
    if (scene.linearTolerance >= 1.0) physics.fail("physics.cg_tolerance", "must be below 1");
    const double threads = physics.number("threads", 1, 1, false);
    if (threads != std::floor(threads) || threads > 64) {
      std::ostringstream given;
      given << threads;
      physics.fail("physics.threads",
                   "= " + given.str() + "; expected a whole number from 1 to 64");
    }
    scene.threads = static_cast<int>(threads);
    scene.femUpdateLatency_s = physics.number("fem_update_latency_ms", 100.0, 0.0, false) / 1000.0;
    if (physics.has("fem_update_latency_ms") && scene.model != "fem-haptic-rate") {
      physics.fail("physics.fem_update_latency_ms", "is for effects.model fem-haptic-rate");
    }
    // A body that answers the probe a whole second late follows nothing a hand does.
    if (scene.femUpdateLatency_s > 1.0) {
      std::ostringstream given;
      given << scene.femUpdateLatency_s * 1000.0;
      physics.fail("physics.fem_update_latency_ms",
                   "= " + given.str() + " is out of range; expected 0 to 1000");
    }
  }
  if (fields.has("assessment")) {
    const Fields assessment(fields.at("assessment"), "assessment", source,
                            {"force_threshold_n", "damage_stretch"});
    scene.assessment.toolForceThreshold_N =
        assessment.number("force_threshold_n", scene.assessment.toolForceThreshold_N, 0.0, true);
    if (assessment.has("damage_stretch"))
      scene.assessment.damageStretch = assessment.number("damage_stretch", 0.0, 1.0, true);
  }
  // The body at its own rate is held by its fixed nodes (and a frictionless tray where the scene
  // has one: sim/HapticRateBody.h), and it is there for the probe.
  if (scene.model == "fem-haptic-rate") {
    if (!scene.instrument)
      fields.fail("instrument", "is missing; effects.model fem-haptic-rate is the probe's model");
    if (scene.tray && scene.tray->friction > 0.0)
      fields.fail("tray.friction",
                  "is not modelled with effects.model fem-haptic-rate (its tray is frictionless); "
                  "leave it out");
    if (!scene.fixed.box_m && scene.fixed.nodes.empty())
      fields.fail("fixed_region", "is missing; effects.model fem-haptic-rate holds the body by it");
  }
  // Its fixed initial Hessian is built from the springs' rest stiffness.
  if (scene.model == "fem" && scene.integrator == "quasi-newton") {
    fields.fail("physics.integrator",
                "= \"quasi-newton\" is for the springs model; use implicit or explicit with "
                "effects.model fem");
  }
  // Its initial Hessian carries the volume term's cube cells (QuasiNewtonSolver.h).
  if (scene.volumeCells == "nodes" && scene.integrator == "quasi-newton") {
    fields.fail("physics.integrator",
                "= \"quasi-newton\" takes the volume term per cube; use implicit or explicit with "
                "effects.volume_cells nodes");
  }
  return scene;
}

}  // namespace tissuesim
