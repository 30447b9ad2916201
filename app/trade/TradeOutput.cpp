// SPDX-License-Identifier: Apache-2.0
#include "app/trade/TradeOutput.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <vtkImageData.h>

#include "analysis/TradeFront.h"
#include "app/CommandError.h"
#include "app/HeadlessDisplay.h"
#include "render/CurveChart.h"
#include "render/OffscreenImage.h"

namespace tissuesim::app {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kBudget_ms = 1.0;
/// Errors (%) closer than this are ties on the fronts: the tables show whole per cents, and
/// rows that give the same forces to a few digits (Newton's settings) are not better for it.
constexpr double kErrorResolution_percent = 0.5;

std::string format(const char* pattern, double value) {
  if (!std::isfinite(value)) return "";
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

/// A CSV field in quotes, its own quotes doubled (RFC 4180).
std::string quoted(const std::string& text) {
  std::string field = "\"";
  for (const char c : text) {
    if (c == '"') field += '"';
    field += c;
  }
  return field + '"';
}

std::string depthLabel(double depth_m) { return format("%g", depth_m * 1e3); }

bool isFem(const TradeMap& map, std::size_t row) { return map.rows[row].femRefinement > 0; }
bool isOrganFem(const TradeMap& map, std::size_t row) { return map.rows[row].isOnOrganMesh(); }

/// The largest |value|; NaN for none.
double largestMagnitude(const std::vector<double>& values) {
  if (values.empty()) return kNan;
  double largest = 0.0;
  for (const double v : values) largest = std::max(largest, std::abs(v));
  return largest;
}
/// Whether the row has a tensile R^2: the lattice's rows, springs and tets (the FEM
/// reference's own is `tensile --model fem`).
bool hasTensile(const TradeMap& map, std::size_t row) {
  return !isFem(map, row) && !isOrganFem(map, row);
}
/// Whether it has an unloading R^2 too: the springs' (the tets have no softening).
bool hasUnloadingTensile(const TradeMap& map, std::size_t row) {
  return hasTensile(map, row) && map.rows[row].model == "springs";
}

/// The machine, in a line: its processor and thread count.
std::string machineLine() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  std::string model = "unknown processor";
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

/// A row's position on one of the map's axes.
using MapAxis = double (*)(const TradeMap&, std::size_t);

/// The rows on the Pareto front of (cost, error), in increasing cost: the block's by default.
std::vector<int> front(const TradeMap& map, MapAxis costAxis = stepCost,
                       MapAxis errorAxis = worstError) {
  std::vector<double> cost;
  std::vector<double> error;
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    cost.push_back(costAxis(map, r));
    error.push_back(errorAxis(map, r));
  }
  return paretoFront(cost, error, kErrorResolution_percent);
}

/// The front's rows in Markdown, a line each: its name, cost (ms) and error (%), and whether it
/// is over the 1 ms budget.
std::string frontList(const TradeMap& map, MapAxis costAxis = stepCost,
                      MapAxis errorAxis = worstError) {
  std::string list;
  for (const int r : front(map, costAxis, errorAxis)) {
    const auto i = static_cast<std::size_t>(r);
    list.append("- ").append(map.rows[i].name).append(": ");
    list.append(format("%.3f", costAxis(map, i))).append(" ms, ");
    list.append(format("%.0f", errorAxis(map, i))).append(" %");
    if (costAxis(map, i) > kBudget_ms) list.append(" (over the 1 ms budget)");
    list.append("\n");
  }
  return list;
}

/// The growth exponent of the median step with springs over the rows of one knob.
double scalingExponent(const TradeMap& map, const std::string& knob) {
  std::vector<double> springs;
  std::vector<double> time;
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    if (map.rows[r].knob != knob || !map.measurements[r].failure.empty()) continue;
    springs.push_back(map.measurements[r].cost.springs);
    time.push_back(map.measurements[r].cost.stepMedian_ms);
  }
  return powerLawExponent(springs, time);
}

}  // namespace

std::vector<double> forceErrors(const std::vector<double>& forces,
                                const std::vector<double>& reference) {
  std::vector<double> errors;
  for (std::size_t d = 0; d < std::min(forces.size(), reference.size()); ++d)
    errors.push_back(100.0 * (forces[d] / reference[d] - 1.0));
  return errors;
}

double worstError(const TradeMap& map, std::size_t row) {
  const TradeMeasurement& m = map.measurements[row];
  if (!m.failure.empty()) return kNan;
  // The FEM's and the FEM at its own rate's block forces are its static column (the latter at 2
  // mm/s through its scheme, which follows no probe at the pace's 4 cm/s).
  const std::vector<double>& forces =
      isFem(map, row) || map.rows[row].isHapticRate() ? m.staticForce_N : m.paceForce_N;
  return largestMagnitude(forceErrors(forces, map.reference.force_N));
}

double stepCost(const TradeMap& map, std::size_t row) {
  if (isFem(map, row) || !map.measurements[row].failure.empty()) return kNan;
  return map.measurements[row].cost.stepMedian_ms;
}

double worstOrganError(const TradeMap& map, std::size_t row) {
  const TradeMeasurement& m = map.measurements[row];
  if (!m.failure.empty() || !m.organFailure.empty()) return kNan;
  const std::vector<double> errors = forceErrors(m.organForce_N, map.organReference_N);
  return errors.size() < map.organReference_N.size() ? kNan : largestMagnitude(errors);
}

double organStepCost(const TradeMap& map, std::size_t row) {
  const TradeMeasurement& m = map.measurements[row];
  if (!m.failure.empty() || !m.organFailure.empty() || !(m.organStepMedian_ms > 0.0)) return kNan;
  return m.organStepMedian_ms;
}

std::string tradeCsv(const TradeMap& map) {
  std::string csv =
      "knob,name,springs,nodes,cell_mm,law,volume_term_kpa,integrator,newton_iterations,"
      "cg_tolerance,threads,startup_s,step_median_ms,step_p99_ms,steps_per_s,peak_memory_mb,"
      "events,mesh,strain_cells";
  const std::vector<double>& depths = map.settings.depths_m;
  for (const char* kind : {"static", "pace"}) {
    for (const double d : depths)
      csv += ",force_" + std::string(kind) + "_" + depthLabel(d) + "mm_n";
    for (const double d : depths)
      csv += ",error_" + std::string(kind) + "_" + depthLabel(d) + "mm_percent";
  }
  for (const char* kind : {"force", "error"}) {
    for (const double d : map.settings.organDepths_m)
      csv += ",organ_" + std::string(kind) + "_" + depthLabel(d) +
             (*kind == 'f' ? "mm_n" : "mm_percent");
  }
  if (!map.settings.organDepths_m.empty()) {
    csv +=
        ",organ_events,organ_failure,organ_step_median_ms,organ_step_p99_ms,organ_steps_per_s,"
        "organ_worst_error_percent,organ_pareto";
  }
  csv +=
      ",worst_error_percent,surface_rms_mm,surface_max_mm,tensile_r2_loading,"
      "tensile_r2_unloading,failed_steps,pareto,failure\n";
  const std::vector<int> onFront = front(map);
  const std::vector<int> onOrganFront = front(map, organStepCost, worstOrganError);
  const auto isIn = [](const std::vector<int>& rows, std::size_t r) {
    return std::find(rows.begin(), rows.end(), static_cast<int>(r)) != rows.end();
  };
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    const TradeRow& row = map.rows[r];
    const TradeMeasurement& m = map.measurements[r];
    const bool fem = isFem(map, r);
    const bool organFem = isOrganFem(map, r);
    std::vector<std::string> fields = {row.knob,
                                       quoted(row.name),
                                       std::to_string(m.cost.springs),
                                       std::to_string(m.cost.nodes),
                                       organFem ? "" : format("%.3f", map.cellEdges_m[r] * 1e3),
                                       fem                  ? "fem"
                                       : row.isQuadratic()  ? "fem-quadratic"
                                       : row.isHapticRate() ? "fem-haptic-rate"
                                       : organFem           ? "fem-organ"
                                       : row.model == "fem" ? "fem-tets"
                                                            : row.law,
                                       format("%g", row.bulkModulus_Pa / 1e3),
                                       fem ? "static" : row.integrator,
                                       fem ? "" : std::to_string(row.newtonIterations),
                                       fem ? "" : format("%g", row.cgTolerance),
                                       fem ? "1" : std::to_string(row.threads),
                                       format("%.3f", m.cost.startup_s),
                                       format("%.4f", m.cost.stepMedian_ms),
                                       format("%.4f", m.cost.stepP99_ms),
                                       format("%.1f", m.cost.stepsPerSecond),
                                       format("%.1f", m.cost.peakMemory_MB),
                                       std::to_string(m.cost.events),
                                       quoted(organFem ? row.organMeshLabel
                                              : fem    ? std::string("block")
                                                       : std::string("lattice")),
                                       row.model == "fem" ? row.strainCells : ""};
    for (const std::vector<double>* forces : {&m.staticForce_N, &m.paceForce_N}) {
      const std::vector<double> errors = forceErrors(*forces, map.reference.force_N);
      for (std::size_t d = 0; d < depths.size(); ++d)
        fields.push_back(d < forces->size() ? format("%.5g", (*forces)[d]) : "");
      for (std::size_t d = 0; d < depths.size(); ++d)
        fields.push_back(d < errors.size() ? format("%.2f", errors[d]) : "");
    }
    const std::vector<double> organErrors = forceErrors(m.organForce_N, map.organReference_N);
    const std::size_t organDepths = map.settings.organDepths_m.size();
    for (std::size_t d = 0; d < organDepths; ++d)
      fields.push_back(d < m.organForce_N.size() ? format("%.5g", m.organForce_N[d]) : "");
    for (std::size_t d = 0; d < organDepths; ++d)
      fields.push_back(d < organErrors.size() ? format("%.2f", organErrors[d]) : "");
    if (organDepths > 0) {
      fields.push_back(m.organForce_N.empty() ? "" : std::to_string(m.organEvents));
      fields.push_back(quoted(m.organFailure));
      const bool timed = std::isfinite(organStepCost(map, r));
      fields.push_back(timed ? format("%.4f", m.organStepMedian_ms) : "");
      fields.push_back(timed ? format("%.4f", m.organStepP99_ms) : "");
      fields.push_back(timed ? format("%.1f", m.organStepsPerSecond) : "");
      fields.push_back(format("%.2f", worstOrganError(map, r)));
      fields.push_back(isIn(onOrganFront, r) ? "1" : "0");
    }
    const bool isOnFront = isIn(onFront, r);
    for (std::string field :
         {format("%.2f", worstError(map, r)), organFem ? "" : format("%.4f", m.surfaceRms_mm),
          organFem ? "" : format("%.4f", m.surfaceMax_mm),
          hasTensile(map, r) ? format("%.6f", m.tensileLoadingR2) : "",
          hasUnloadingTensile(map, r) ? format("%.6f", m.tensileUnloadingR2) : "",
          std::to_string(m.failedSteps), std::string(isOnFront ? "1" : "0"), quoted(m.failure)}) {
      fields.push_back(std::move(field));
    }
    for (std::size_t f = 0; f < fields.size(); ++f) {
      if (f > 0) csv += ',';
      csv += fields[f];
    }
    csv += '\n';
  }
  return csv;
}

std::string tradeMarkdown(const TradeMap& map) {
  const std::vector<double>& depths = map.settings.depths_m;
  const auto joined = [](const std::vector<double>& values, const char* pattern) {
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i > 0) text += " / ";
      text += format(pattern, values[i]);
    }
    return text;
  };
  std::vector<double> depths_mm;
  for (const double d : depths) depths_mm.push_back(d * 1e3);

  std::ostringstream md;
  md << "# The speed/accuracy map\n\n`tissuesim trade" << (map.settings.isQuick ? " --quick" : "")
     << "`: tissue " << map.tissueName << ", scene " << map.sceneName << "; " << machineLine()
     << "; " << format("%.0f", map.wall_s) << " s.\n\n";
  md << "**Cost** is the bundled scene's default poke (4 cm along the tool and back, 2 s"
     << (map.settings.pokeSeconds > 0.0
             ? "; here its first " + format("%g", map.settings.pokeSeconds) + " s"
             : std::string())
     << ") on the "
        "liver lattice-meshed to each row's spring count, with the row's knobs, each run in a "
        "process of its own (memory: its peak resident set above its start), "
     << map.settings.costRounds
     << " times with the rows interleaved (the medians). **Error** is the "
        "indentation test: a 60 x 60 x 30 mm block, bottom held, pressed at its centre by the "
        "bundled 2.5 mm probe, meshed with the same cube edge as the row's liver lattice; the "
        "probe's force at each depth, static and at the bundled poke's 4 cm/s stepped by the "
        "row's integrator, against the FEM reference (quadratic tets, mean dilatation, "
        "refinement "
     << map.settings.referenceRefinement << ": " << map.reference.nodes
     << " nodes in the quarter block, " << format("%.0f", map.reference.seconds) << " s).\n\n";
  md << "FEM reference force at " << joined(depths_mm, "%g")
     << " mm: " << joined(map.reference.force_N, "%.4g") << " N.\n\n";

  const bool hasOrgan = !map.organReference_N.empty();
  std::vector<double> organDepths_mm;
  for (const double d : map.settings.organDepths_m) organDepths_mm.push_back(d * 1e3);
  if (hasOrgan) {
    md << "**The liver poke**: the bundled liver itself, weightless and held by its fixed region, "
          "poked along the instrument's axis at "
       << format("%g", map.settings.organSpeed_m_s * 1e3)
       << " mm/s (`tissuesim organ-poke`), against the FEM on a conformal mesh of its drawn "
          "surface: "
       << joined(map.organReference_N, "%.4g") << " N at " << joined(organDepths_mm, "%g")
       << " mm below the surface. Measured on every row but the FEM on the lattice (minutes a "
          "row there) and the block's FEM. The FEM on the organ's meshes (conformal with the "
          "drawn surface, graded towards the probe: assets/meshes/README.md; its volume per node "
          "at "
       << format("%g", map.settings.organMeshBulkModulus_Pa / 1e6)
       << " MPa, contact on the mesh's boundary) is measured on this poke alone: its step "
          "times are the liver poke's, not the bundled poke's (whose 4 cm are past the "
          "continuum's equilibrium). The FEM reference's own element on the same meshes "
          "(quadratic tets, one dilatation each, at the reference's bulk modulus) is solved "
          "statically at each depth: its step is a Newton iteration (the Hessian assembled, "
          "factorised by CHOLMOD, a line search), its events the solves left unconverged, its "
          "forces kept in the output folder once solved. The same element at its own rate with "
          "the probe's contact at 1 kHz is a scene (`--haptic-rate-scene`, `effects.model: "
          "fem-haptic-rate`; by default the bundled `liver-fem-refined.json`, its body refined "
          "where the tool aims, each update one Newton iteration used 60 ms after it starts, "
          "the contact sampled on its surface and solved each millisecond): its liver poke runs "
          "through the scene's own steps, its "
          "step is the scene's (the contact's, an update taken in now and then), its events the "
          "scene's; its block error is the same scheme and settings on `indent`'s body refined "
          "towards the probe (`indent --models fem-haptic-rate`) at the liver poke's speed, in the "
          "static column.\n\n";
  } else {
    md << "No liver poke: " << map.organNote << ".\n\n";
  }
  md << "| setting | springs | cell (mm) | step median / p99 (ms) | steps/s | start-up (s) | "
        "memory (MB) | instability events on the poke | force error, static (%) | force error, at "
        "pace (%) | surface RMS / max (mm) | tensile R^2 loading / unloading (%) |"
     << (hasOrgan ? " liver poke error (%) |" : "") << "\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|" << (hasOrgan ? "---|" : "") << "\n";
  const auto organCell = [&](const TradeMeasurement& m, bool isStatic = false,
                             const char* eventName = nullptr) {
    std::string cell;
    if (!hasOrgan) return cell;
    if (!m.organFailure.empty()) {
      cell.append(" failed: ").append(m.organFailure);
    } else if (m.organForce_N.empty()) {
      cell.append(" -");
    } else {
      cell.append(" ").append(joined(forceErrors(m.organForce_N, map.organReference_N), "%+.0f"));
      if (m.organEvents > 0) {
        cell.append(" (").append(std::to_string(m.organEvents));
        if (eventName != nullptr) {
          cell.append(" ").append(eventName).append(")");
        } else if (isStatic) {
          cell.append(m.organEvents == 1 ? " unconverged solve)" : " unconverged solves)");
        } else {
          cell.append(m.organEvents == 1 ? " event)" : " events)");
        }
      }
    }
    return cell.append(" |");
  };
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    const TradeRow& row = map.rows[r];
    const TradeMeasurement& m = map.measurements[r];
    md << "| " << row.name << " | ";
    if (!m.failure.empty()) {
      md << "failed: " << m.failure << " |||||||||||" << (hasOrgan ? "|" : "") << "\n";
      continue;
    }
    const std::string staticErrors =
        joined(forceErrors(m.staticForce_N, map.reference.force_N), "%+.0f");
    const std::string surface =
        format("%.3f", m.surfaceRms_mm) + " / " + format("%.3f", m.surfaceMax_mm);
    if (isOrganFem(map, r)) {
      // The quadratic tets are solved statically: a step is a Newton iteration, an event a
      // solve left unconverged.
      const bool isStatic = row.isQuadratic();
      const bool isHapticRate = row.isHapticRate();
      md << "- (" << m.cost.nodes << " nodes) | - | " << format("%.3f", m.cost.stepMedian_ms)
         << (isStatic ? " a Newton iteration (liver poke, static)"
                      : " / " + format("%.3f", m.cost.stepP99_ms) + " (liver poke" +
                            (isHapticRate ? ", the contact's step; an FEM update " +
                                                format("%.0f", m.organUpdateMean_ms) + " ms"
                                          : std::string()) +
                            ")")
         << " | " << format("%.0f", m.cost.stepsPerSecond) << " | "
         << format("%.2f", m.cost.startup_s) << " | - | " << m.cost.events
         << (isStatic ? " unconverged solves" : "") << " (liver poke) | "
         << (isHapticRate && !m.staticForce_N.empty() ? staticErrors + " (at the poke's speed)"
                                                      : "-")
         << " | - | - | - |" << organCell(m, isStatic) << "\n";
      continue;
    }
    if (isFem(map, r)) {
      md << "- | - | " << format("%.1f", m.cost.stepMedian_ms / 1e3)
         << " s a load step (block) | - | - | - | - | " << staticErrors << " | - | " << surface
         << " | - |" << organCell(m) << "\n";
      continue;
    }
    md << m.cost.springs << " | " << format("%.1f", map.cellEdges_m[r] * 1e3) << " | "
       << format("%.3f", m.cost.stepMedian_ms) << " / " << format("%.3f", m.cost.stepP99_ms)
       << " | " << format("%.0f", m.cost.stepsPerSecond) << " | "
       << format("%.2f", m.cost.startup_s) << " | " << format("%.0f", m.cost.peakMemory_MB) << " | "
       << m.cost.events << " | " << staticErrors << " | "
       << joined(forceErrors(m.paceForce_N, map.reference.force_N), "%+.0f")
       << (m.failedSteps > 0 ? " (" + std::to_string(m.failedSteps) + " steps failed)" : "")
       << " | " << surface << " | "
       << (hasTensile(map, r)
               ? format("%.2f", 100.0 * m.tensileLoadingR2) + " / " +
                     (hasUnloadingTensile(map, r) ? format("%.2f", 100.0 * m.tensileUnloadingR2)
                                                  : std::string("- (virgin; no softening)"))
               : std::string("-"))
       << " |" << organCell(m) << "\n";
  }
  md << "\nForce errors at " << joined(depths_mm, "%g")
     << " mm, signed (negative: softer than the FEM)"
     << (hasOrgan ? std::string("; the liver poke's at ")
                        .append(joined(organDepths_mm, "%g"))
                        .append(" mm")
                  : std::string())
     << ". The surface columns compare the top "
        "face's displacement with the FEM's at the last depth, every 1 mm to 15 mm from the "
        "axis along x and the diagonal.\n\n";

  md << "## The Pareto front\n\nThe largest |force error| at pace over the depths (the FEM at "
        "its own rate: at the liver poke's speed), against the median step: no other setting is "
        "both faster and closer (by more than half a point).\n\n";
  md << frontList(map);

  if (hasOrgan) {
    md << "\n## The Pareto front on the liver poke\n\nThe largest |force error| over the liver "
          "poke's depths, against its median step (each row's own liver poke; the rows that "
          "differ in threads alone share their forces and are left out), ties within half a point "
          "going to the cheaper:\n\n";
    md << frontList(map, organStepCost, worstOrganError);
  }

  md << "\n## Scaling\n\nMedian step against springs, fitted as t ~ springs^p: p = "
     << format("%.2f", scalingExponent(map, "resolution"))
     << " with the bundled threads, p = " << format("%.2f", scalingExponent(map, "threads"))
     << " on one thread. Speed-up from one thread to the bundled count:";
  for (std::size_t r = 0; r < map.rows.size(); ++r) {
    if (map.rows[r].knob != "threads" || !map.measurements[r].failure.empty()) continue;
    for (std::size_t s = 0; s < map.rows.size(); ++s) {
      if (map.rows[s].knob == "resolution" &&
          map.rows[s].targetSprings == map.rows[r].targetSprings &&
          map.measurements[s].failure.empty()) {
        md << " " << map.measurements[s].cost.springs << " springs "
           << format("%.2f", map.measurements[r].cost.stepMedian_ms /
                                 map.measurements[s].cost.stepMedian_ms)
           << "x;";
      }
    }
  }
  md << "\n";
  return md.str();
}

namespace {

/// A group of the plot's points: the rows of one knob (and, for the FEM on the organ's meshes,
/// one kind of strain cell).
struct PlotGroup {
  const char* knob;
  const char* strainCells;  ///< nullptr: any
  const char* name;
  std::array<unsigned char, 3> rgb;
  bool isLine;
};

constexpr PlotGroup kPlotGroups[] = {
    {"resolution", nullptr, "resolution, bundled settings", {200, 40, 30}, true},
    {"threads", nullptr, "resolution, 1 thread", {230, 140, 40}, false},
    {"model", nullptr, "spring law", {30, 90, 200}, false},
    {"volume", nullptr, "volume term", {120, 60, 170}, false},
    {"integrator", nullptr, "integrator", {30, 150, 60}, false},
    {"fem-tets", nullptr, "fem on the lattice (tets)", {20, 160, 170}, true},
    {"fem-organ", "tets", "fem per tet, organ's graded meshes", {110, 110, 30}, true},
    {"fem-organ", "faces", "fem per face, organ's graded meshes", {200, 60, 150}, true},
    {"fem-quadratic",
     nullptr,
     "fem quadratic tets (static), organ's graded meshes",
     {90, 90, 90},
     true},
    {"fem-haptic-rate",
     nullptr,
     "fem quadratic tets at their own rate, contact at 1 kHz",
     {230, 0, 230},
     false}};

/// Error against cost on log axes, a series per group, the Pareto front and the 1 ms budget.
void writeMapPlot(const TradeMap& map, const std::string& path, const std::string& title,
                  const std::string& costLabel, const std::string& errorLabel, MapAxis costAxis,
                  MapAxis errorAxis) {
  const HeadlessDisplay display;
  CurveChart chart(title, costLabel, errorLabel);
  std::vector<ChartSeries> series;
  double lowest = std::numeric_limits<double>::infinity();
  double highest = 0.0;
  double fastest = kBudget_ms;
  double slowest = kBudget_ms;
  for (const PlotGroup& group : kPlotGroups) {
    ChartSeries points;
    points.name = group.name;
    points.rgb = group.rgb;
    points.isPoints = true;
    for (std::size_t r = 0; r < map.rows.size(); ++r) {
      if (map.rows[r].knob != group.knob) continue;
      if (group.strainCells && map.rows[r].strainCells != group.strainCells) continue;
      const double x = costAxis(map, r);
      const double y = std::max(errorAxis(map, r), 0.01);  // a log axis has no 0
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      points.x.push_back(x);
      points.y.push_back(y);
      lowest = std::min(lowest, y);
      highest = std::max(highest, y);
      fastest = std::min(fastest, x);
      slowest = std::max(slowest, x);
    }
    if (points.x.empty()) continue;
    if (group.isLine && points.x.size() > 1) {
      ChartSeries line = points;
      line.name = std::string(group.name) + " (joined)";
      line.isPoints = false;
      line.width = 1.0f;
      series.push_back(line);
    }
    series.push_back(points);
  }
  ChartSeries paretoLine;
  paretoLine.name = "Pareto front";
  paretoLine.rgb = {0, 0, 0};
  paretoLine.isDashed = true;
  for (const int r : front(map, costAxis, errorAxis)) {
    paretoLine.x.push_back(costAxis(map, static_cast<std::size_t>(r)));
    paretoLine.y.push_back(std::max(errorAxis(map, static_cast<std::size_t>(r)), 0.01));
  }
  series.push_back(paretoLine);
  if (std::isfinite(lowest)) {
    ChartSeries budget;
    budget.name = "1 ms budget (1 kHz)";
    budget.rgb = {120, 120, 120};
    budget.isDashed = true;
    budget.x = {kBudget_ms, kBudget_ms};
    budget.y = {lowest, highest};
    series.push_back(budget);
  }
  chart.setSeries(series);
  chart.setLogScale(true, true);
  // A margin round every point and the budget line: a point on an axis's end is half hidden.
  if (std::isfinite(lowest))
    chart.setRanges(fastest / 1.3, slowest * 1.3, lowest / 1.5, highest * 1.5);
  const vtkSmartPointer<vtkImageData> image = renderOffscreen(chart.renderer(), 1000, 700);
  try {
    writePng(image, path);
  } catch (const std::runtime_error& error) {
    throw CommandError(error.what());
  }
}

}  // namespace

void writeTradePlot(const TradeMap& map, const std::string& path) {
  writeMapPlot(map, path, "Speed against accuracy (" + map.tissueName + ")",
               "median step on the liver (ms)", "largest |force error| vs the FEM, at pace (%)",
               stepCost, worstError);
}

void writeLiverTradePlot(const TradeMap& map, const std::string& path) {
  writeMapPlot(map, path, "Speed against accuracy on the liver poke (" + map.tissueName + ")",
               "median step on the liver poke (ms)",
               "largest |force error| vs the FEM on the liver poke (%)", organStepCost,
               worstOrganError);
}

}  // namespace tissuesim::app
