// SPDX-License-Identifier: Apache-2.0
#pragma once
// The speed/accuracy map's rows (`tissuesim trade`): each a setting of the simulator's knobs,
// measured for its cost on the bundled liver and for its error against the FEM reference.
//
// Cost: the bundled scene with the row's knobs (its liver lattice-meshed from the drawn surface
// to the row's spring count, its law, volume term, integrator and threads) run through the
// default poke (4 cm along the tool and back, 2 s) in a child process: start-up (mesh, tables,
// calibration, the settled start), each step's wall time (median, 99th percentile), steps per
// second, and the child's peak resident memory above what it started with.
//
// Error: the indentation test (analysis/IndentationExperiment.h) on a network with the same cube
// edge as the row's liver lattice, its law and volume term: the probe's force at each depth, static
// and at the scene's pace (the bundled poke's 4 cm/s, stepped by the row's integrator), against
// the FEM reference's static force; the top face's displacement against the FEM's; and the
// tensile test's R^2 against sedf. And, where the scene's FEM reference of the liver poke is at
// hand (organ-poke --fem-cache), each row's force on that poke (OrganPoke.h) and its steps' wall
// time there.
//
// The FEM on meshes conformal to the organ (knob "fem-organ": the tissue's energy per tet or per
// face, a volume per node, contact on the mesh's boundary) has no block and no lattice: its
// rows are measured on the liver poke alone, error and cost.

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "analysis/IndentationExperiment.h"
#include "mesh/TriangleSurface.h"
#include "sim/SceneFile.h"

namespace tissuesim::app {

struct LoadedTissue;

/// One setting of the knobs. `knob` says which one the row varies from the bundled scene's.
struct TradeRow {
  /// resolution, threads, model, volume, integrator, fem-tets, fem-organ, reference
  std::string knob;
  std::string name;
  int targetSprings = 5300;
  std::string law = "eesm";
  double bulkModulus_Pa = 0.0;
  std::string integrator = "implicit";
  int newtonIterations = 1;
  double cgTolerance = 1e-3;
  int threads = 2;
  /// "springs", or "fem": the tets' FEM on the same lattice (effects.model fem), its volume term
  /// at bulkModulus_Pa, no softening.
  std::string model = "springs";
  int femRefinement = 0;  ///< > 0: an FEM row (cost on the block, not the liver)
  /// Non-empty: the FEM on this tet mesh of the organ (metres, conformal with the drawn surface),
  /// the drawn surface left out (contact on the mesh's boundary), a volume per node at
  /// bulkModulus_Pa and the isochoric strain per strainCells ("tets" or "faces").
  std::string organMeshPath;
  std::string organMeshLabel;  ///< what the mesh is, for the table: "2.5 / 12 mm, 965 nodes"
  std::string strainCells = "tets";
  /// "linear" (the simulator's tets, as above), or "quadratic": on the organ's mesh, the FEM
  /// reference's own element (10-node tets, one dilatation each, kappa bulkModulus_Pa) solved
  /// statically at each depth, its step a Newton iteration (assembly, factorisation, line search).
  /// Or "haptic-rate": the same element at its own rate with the probe's contact, sampled on its
  /// surface, at 1 kHz (fem/HapticRateFem.h), its step the contact's: the settings'
  /// hapticRateScene as a user runs it, organMeshPath its tet mesh.
  std::string element = "linear";

  /// The FEM on an organ's mesh: measured on the liver poke alone, error and cost.
  bool isOnOrganMesh() const { return !organMeshPath.empty(); }
  bool isQuadratic() const { return element == "quadratic"; }
  bool isHapticRate() const { return element == "haptic-rate"; }
};

/// A mesh of the organ on which the FEM is a row of the map.
struct OrganMesh {
  std::string path;
  std::string label;
};

/// A row's cost on the liver (FEM rows: on the block, stepMedian_ms a static solve per load
/// step).
struct TradeCost {
  int springs = 0;
  int nodes = 0;
  double startup_s = 0.0;
  double stepMedian_ms = 0.0;
  double stepP99_ms = 0.0;
  double stepsPerSecond = 0.0;
  double peakMemory_MB = 0.0;
  long events = 0;
  std::string failure;  ///< what stopped the run, when something did
};

struct TradeMeasurement {
  TradeCost cost;
  // On the block.
  std::vector<double> staticForce_N;
  std::vector<double> paceForce_N;  ///< empty for FEM rows
  double surfaceRms_mm = 0.0;
  double surfaceMax_mm = 0.0;
  int failedSteps = 0;  ///< at the pace: refused or non-finite steps
  // The tensile test (the lattice rows): the lowest loading and unloading R^2 over the cycles
  // (the tets: loading against the virgin curve, no unloading).
  double tensileLoadingR2 = 0.0;
  double tensileUnloadingR2 = 0.0;
  // The liver poke (OrganPoke.h), weightless, at the settings' organ depths.
  std::vector<double> organForce_N;
  long organEvents = 0;
  /// The liver poke's steps' wall time (ms), median and 99th percentile, and the steps a
  /// second of its stepping alone.
  double organStepMedian_ms = 0.0;
  double organStepP99_ms = 0.0;
  double organStepsPerSecond = 0.0;
  double organUpdateMean_ms = 0.0;  ///< a haptic-rate row's FEM update, its wall time
  std::string organFailure;         ///< what stopped the liver poke, when something did
  std::string failure;              ///< what stopped the row, when something did
};

struct TradeSettings {
  bool isQuick = false;
  std::vector<int> resolutions;  ///< springs on the liver
  std::vector<double> depths_m;  ///< indentation depths, increasing
  int referenceRefinement = 1;   ///< the FEM reference's
  std::vector<int> femRows;      ///< coarser FEM refinements measured as rows
  /// Lattices (springs on the liver) on which the tets' FEM is a row, with this bulk modulus
  /// (the reference's: the same continuum, so its error can converge).
  std::vector<int> tetResolutions;
  double tetBulkModulus_Pa = 0.0;
  int tensileResolution = 1;  ///< cells across the tensile specimen's thickness
  int tensilePoints = 10;     ///< per branch
  /// Each row's liver run is repeated this many times, the rows interleaved (a shared machine's
  /// speed drifts from minute to minute), and each timing is the median over the rounds.
  int costRounds = 3;
  double pokeSeconds = 0.0;  ///< the cost runs' simulated time; 0: the whole poke (2 s)
  /// The liver poke's depths below the surface (m), increasing; empty: no liver poke.
  std::vector<double> organDepths_m;
  double organSpeed_m_s = 0.002;  ///< its probe's speed
  /// Meshes of the organ on which the FEM (per tet, then per face) is a row, measured on the
  /// liver poke alone; none without a liver poke.
  std::vector<OrganMesh> organMeshes;
  double organMeshBulkModulus_Pa = 10e6;  ///< their volume per node's
  /// The scene of the reference's element at its own rate with the contact at 1 kHz
  /// (effects.model fem-haptic-rate) that is a row: the liver poke through the scene's own
  /// steps, weightless, and the block through the same scheme and settings on indent's body
  /// refined towards the probe (IndentationBodyGrading); none without a liver poke.
  std::optional<SceneDescription> hapticRateScene;
  /// Where the quadratic rows' forces, once solved (minutes), are kept for the next map, beside
  /// those kept next to each mesh (`<mesh's stem>-poke.csv`, FemForceCache.h); empty: nowhere.
  std::string organCacheFolder;
};

/// The rows of the map: the bundled scene at each resolution (two threads, then one), and at
/// the resolution nearest the bundled mesh's: the other spring laws, no volume term, the other
/// integrators and Newton settings; the tets' FEM on the lattices; the FEM on the organ's meshes
/// (per tet, per face, then the reference's quadratic tets); then the FEM rows.
std::vector<TradeRow> tradeRows(const SceneDescription& bundled, const TradeSettings& settings);

/// The cost of `row` on the liver, in a child process (or the failure that stopped it), over the
/// first `duration_s` of the poke (0: all of it). Its start-up includes all the scene's own
/// start-up work, the calibration among it.
TradeCost measureLiverCost(const SceneDescription& bundled, const TradeRow& row, double duration_s);
/// One cost per round of the same row (at least one): their timings' medians, the largest
/// memory and event count; the first failure, if any.
TradeCost medianOfRounds(const std::vector<TradeCost>& rounds);
/// The RMS and largest distance (mm) between two samplings of the top face's displacement
/// into `out`'s surface fields.
void setSurfaceGap(const std::vector<Eigen::Vector3d>& model_m,
                   const std::vector<Eigen::Vector3d>& reference_m, TradeMeasurement& out);

/// The FEM on the indentation block at the settings' depths and this refinement.
IndentationCurve measureReference(const LoadedTissue& tissue, const TradeSettings& settings,
                                  int refinement);

/// The error side of the spring rows, each measurement made once and shared by the rows that
/// need it (the threads and integrator rows share their network's static solve and tensile test).
class TradeErrors {
 public:
  /// `tissue` must outlive this object.
  TradeErrors(const LoadedTissue& tissue, const SceneDescription& bundled,
              const TradeSettings& settings);

  /// The cube edge (m) of the liver's lattice of about `springs` springs.
  double cellEdge(int springs) const;
  /// The simulator's factor on V_e for a volume term (Pa), measured once each.
  double stiffnessScale(double bulkModulus_Pa);
  /// The block and tensile fields of `out` for spring row `row`, against `reference`.
  void measure(const TradeRow& row, const IndentationCurve& reference, TradeMeasurement& out);
  /// The liver poke's fields of `out` for row `row` (its forces are the same for any thread
  /// count, so measured once for rows that differ in threads alone; the step times are those of
  /// the first row measured). For a row on an organ mesh, its cost fields too: nodes, start-up,
  /// the steps' median, 99th percentile and rate, events (no memory figure: it runs in this
  /// process).
  /// A haptic-rate row's poke runs whole through its scene (seconds); its step is the scene's
  /// (the contact's, an update taken in now and then), its events the scene's. Its block's
  /// forces, at 2 mm/s through the same scheme, go into the row's static forces.
  /// A quadratic row's forces are read where they are kept (TradeSettings::organCacheFolder)
  /// and its Newton iterations timed to the first depth; else solved to every depth (minutes) and
  /// kept when no solve left more than a hundred-thousandth of the deepest force on a node. Its
  /// events, when one left more: the solves that stopped short of the solver's tolerance.
  void measureOrgan(const TradeRow& row, TradeMeasurement& out);

 private:
  void measureQuadraticOrgan(const TradeRow& row, TradeMeasurement& out);
  void measureHapticRateOrgan(TradeMeasurement& out);

  const LoadedTissue& m_tissue;
  SceneDescription m_bundled;
  TradeSettings m_settings;
  TriangleSurface m_surface;  ///< the drawn liver
  std::map<double, double> m_stiffnessScales;
  std::map<std::string, IndentationCurve> m_static;
  std::map<std::string, IndentationCurve> m_pace;
  std::map<std::string, std::pair<double, double>> m_tensile;
  /// A liver poke measured, and the thread count its step times were taken on.
  struct TimedOrganPoke {
    TradeMeasurement measured;
    int threads = 0;
  };
  std::map<std::string, TimedOrganPoke> m_organ;
};

}  // namespace tissuesim::app
