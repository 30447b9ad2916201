// SPDX-License-Identifier: Apache-2.0
#pragma once
// The liver poke against the continuum (`tissuesim organ-poke`, and the map's liver columns in
// `tissuesim trade`): a scene's organ, weightless and held by its fixed region alone (or, with
// organ-poke --weighted, under the scene's gravity and on its tray, settled first), poked along
// its instrument's axis. This file holds the simulator's side and what both sides share; the
// FEM's is analysis/OrganPokeExperiment.h.

#include <cstdint>
#include <string>
#include <vector>

#include "analysis/OrganPokeExperiment.h"
#include "sim/SceneFile.h"

namespace tissuesim::app {

/// The depths below the surface (mm) organ-poke measures by default, those of the bundled
/// liver's kept reference (assets/meshes/liver-fem-poke.csv) that `trade` reads.
inline const std::vector<double> kOrganPokeDepths_mm{1.0, 2.0, 3.0, 4.0, 5.0, 10.0};

/// The tet mesh of an organ at `path` (metres). @throws CommandError naming the file and line
/// when it is not one.
TetMesh readOrganMesh(const std::string& path);

/// `scene` weightless (no gravity, no tray), the continuum reference's conditions.
/// @throws CommandError when it has no instrument or holds listed nodes rather than a box.
SceneDescription weightlessPokeScene(SceneDescription scene);
/// `scene` as it is, under its gravity and on its tray. @throws CommandError as
/// weightlessPokeScene, and when it has no gravity or its tray has friction (the reference's is
/// frictionless).
SceneDescription weightedPokeScene(SceneDescription scene);

/// The FEM's setup for `scene`'s poke to `depths_m` (its gravity and tray, the body at
/// density_kg_m3 where it has gravity).
OrganPokeSetup organPokeSetup(const SceneDescription& scene, const std::vector<double>& depths_m,
                              double density_kg_m3 = OrganPokeSetup{}.density_kg_m3);

/// What the FEM reference's forces depend on (FemForceCache.h): the tissue file, the FEM mesh
/// file, the probe, the fixed box, the bulk modulus and the solver's settings; under gravity, it,
/// the density and the tray.
/// @throws CommandError when a file cannot be read.
std::uint64_t femReferenceKey(const SceneDescription& scene, const std::string& femMeshPath,
                              const OrganPokeSetup& setup, double bulkModulus_Pa);

struct SimulatorPoke {
  std::vector<double> force_N;  ///< along the axis, at each depth
  double seconds = 0.0;         ///< wall time, start-up included
  long steps = 0;               ///< steps taken (refused ones included)
  /// Wall time of the steps alone (stepping_s / steps a step), and each step's. The FEM at its
  /// own rate's steps leave out the time they waited for an update at its latency: run faster
  /// than real time they wait for each, which at 1 kHz is done by then where it takes less than
  /// its latency (updateMean_ms against the scene's fem_update_latency_ms).
  double stepping_s = 0.0;
  std::vector<double> stepTimes_ms;
  int nodes = 0;    ///< the organ's mesh's (the FEM at its own rate: its quadratic nodes)
  long events = 0;  ///< instability events
  /// The kinds of the events the simulation kept (its first 100), with counts
  /// (eventKindSummary).
  std::string eventKinds;
  /// The FEM at its own rate (effects.model fem-haptic-rate): its updates taken in during the
  /// poke and their mean wall time (ms); 0 for other models.
  long updates = 0;
  double updateMean_ms = 0.0;
};

/// The simulator's force along the probe's axis at each depth below where the axis meets the
/// drawn surface (or the tet mesh's boundary), for `scene` as weightlessPokeScene() or
/// weightedPokeScene() makes it: the probe driven at `speed_m_s` from 1 mm above that point (the
/// organ rests until touched; under gravity, the point on the surface settled as the scene
/// opens), the force interpolated between the steps either side of each depth. @throws
/// CommandError when the axis misses the organ or the simulator does not reach the depths.
SimulatorPoke pokeSimulator(const SceneDescription& scene, const std::vector<double>& depths_m,
                            double speed_m_s);

}  // namespace tissuesim::app
