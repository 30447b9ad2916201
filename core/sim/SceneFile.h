// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scene file (JSON): what to simulate. The schema is in docs/scene-file.md. Every path is
// relative to the scene file. What a scene does not name is not built: no surface, no visual
// embedding; no instrument, no collision; the volume term only when asked for.
//
// Errors are SceneFileError, one line naming the file, the field and what was expected.

#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tissuesim {

class SceneFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A tet mesh refined where the instrument first aims (mesh/TetRefinement.h): edges at most
/// finest_m there, the bound growing by `growth` per unit distance, the mesh as read where the
/// bound reaches coarsest_m.
struct SceneTetRefinement {
  double finest_m = 0.004;
  double growth = 2.0;
  double coarsest_m = 0.024;
};

struct SceneMeshSource {
  std::filesystem::path file;  ///< resolved against the scene's folder
  /// > 0: the file's scale; 0: not given, guessed from the file's size (mesh/LengthUnit.h)
  double metresPerUnit = 0.0;
  std::string part;                              ///< surfaces only: one named part, or all
  std::optional<SceneTetRefinement> refinement;  ///< tet meshes only
};

/// How the fixed nodes are chosen: nodes inside an axis-aligned box (m), or listed indices.
struct SceneFixedRegion {
  std::optional<Eigen::AlignedBox3d> box_m;
  std::vector<int> nodes;
};

struct SceneInstrument {
  double shaftRadius_m = 0.0025;
  double shaftLength_m = 0.3;
  Eigen::Vector3d tipStart_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  ///< shaft axis, tip first (unit)
};

/// A flat support under the organ (the tray): the tissue stays on the side of the plane
/// up . y = height_m that `up` points to, pushed back with a pressure of stiffness_Pa_per_m per
/// metre of penetration (a penalty per unit area, so the support's stiffness does not depend on
/// how finely the surface is meshed), with Coulomb friction of coefficient `friction`
/// (dimensionless; 0: frictionless, and no friction field in the step).
struct SceneTray {
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  ///< unit, out of the tray into the tissue
  double height_m = 0.0;
  double stiffness_Pa_per_m = 1e7;
  double friction = 0.0;
};

/// The session assessment's thresholds (sim/SessionAssessment.h, docs/assessment.md).
struct SceneAssessment {
  /// Time above this force on the tool is reported. The default sits three standard deviations
  /// below the mean force at which a blunt rod pushed into intact human liver tore its capsule,
  /// 34.1 +- 8.7 N (Simon et al. 2020, Int. J. Legal Med. 134:1067; lowest 18.1 N): a force a
  /// careful trainee has no reason to reach.
  double toolForceThreshold_N = 8.0;
  std::optional<double> damageStretch;  ///< none: the tissue file's damage_stretch
};

struct SceneDescription {
  std::filesystem::path source;  ///< the scene file
  std::string name;
  std::filesystem::path tissue;
  std::optional<SceneMeshSource> surface;
  std::optional<SceneMeshSource> tetMesh;  ///< or generated from the surface:
  int targetSprings = 0;                   ///< > 0: lattice-mesh the surface to about this many
  SceneFixedRegion fixed;
  Eigen::Vector3d gravity_m_s2 = Eigen::Vector3d::Zero();
  std::optional<SceneTray> tray;  ///< none: nothing supports the organ but the fixed region
  std::optional<SceneInstrument> instrument;
  bool isSoftening = true;
  double bulkModulus_Pa = 0.0;  ///< > 0: volume term on
  /// The volume term's cells: "cubes" (a lattice cube, else a tet; springs/VolumeForceField.h)
  /// or "nodes" (each node's share of its tets; springs/NodalVolumeForceField.h).
  std::string volumeCells = "cubes";
  /// Where the FEM takes the isochoric strain: "tets" (each tet's F; fem/TetIsochoricForceField.h),
  /// "faces" or "nodes" (the mean F over each face's or node's share of its tets: FS-FEM, NS-FEM;
  /// fem/SmoothedStrainForceField.h). With model fem only.
  std::string strainCells = "tets";
  double stiffnessScale = 0.0;  ///< > 0: V_e factor; 0: the lattice's small-strain calibration
  /// What carries the elasticity: "springs" (the EESM network), "fem" (the tissue's
  /// isochoric energy per tet with the volume term per cube; fem/TetIsochoricForceField.h) or
  /// "fem-haptic-rate" (the continuum reference's element at its own rate, the probe's contact
  /// at the haptic rate; sim/HapticRateBody.h).
  std::string model = "springs";
  std::string springLaw = "eesm";
  double timeStep_s = 1e-3;
  std::string integrator = "implicit";
  double massDamping_1_s = 0.0;
  // Implicit: the speed/accuracy trade of these two is measured in docs/performance.md.
  int newtonIterations =
      2;  ///< Newton iterations per step (implicit); per FEM update (fem-haptic-rate)
  double linearTolerance = 1e-6;  ///< CG relative tolerance per Newton iteration
  int threads = 1;                ///< threads for the spring passes (results do not depend on it)
  /// With model fem-haptic-rate: each FEM update used this long after it starts (s; the step
  /// waits for one not done by then), or 0: as soon as it is done (the window's real time alone).
  double femUpdateLatency_s = 0.1;
  SceneAssessment assessment;
};

/// Reads and validates a scene; paths resolved, files checked to exist.
SceneDescription loadSceneFile(const std::filesystem::path& path);

}  // namespace tissuesim
