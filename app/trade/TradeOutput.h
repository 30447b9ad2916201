// SPDX-License-Identifier: Apache-2.0
#pragma once
// What `tissuesim trade` writes: tradeoff.csv (a row per setting, every figure), tradeoff.md
// (the table a reader reads, the Pareto fronts, the scaling fit), tradeoff.png (the block's error
// against time per step on log axes, the front marked, the 1 ms budget drawn) and, with the liver
// poke, tradeoff-liver.png (the same for the liver poke's error and steps).

#include <string>
#include <vector>

#include "app/trade/TradeGrid.h"

namespace tissuesim::app {

struct TradeMap {
  TradeSettings settings;
  std::string tissueName;
  std::string sceneName;
  IndentationCurve reference;  ///< the FEM reference
  /// The liver poke's FEM reference at settings.organDepths_m (empty: no liver poke), and why
  /// there is none when there is none.
  std::vector<double> organReference_N;
  std::string organNote;
  std::vector<TradeRow> rows;
  std::vector<TradeMeasurement> measurements;  ///< one per row
  std::vector<double> cellEdges_m;             ///< per row: its lattice's cube edge (0: FEM)
  double wall_s = 0.0;
};

/// The signed error (%) of each of `forces` against the reference's at the same depth.
std::vector<double> forceErrors(const std::vector<double>& forces,
                                const std::vector<double>& reference);
/// The map's accuracy axis for a row: the largest |error| (%) over the depths at the scene's
/// pace (FEM rows: static); NaN where there is none.
double worstError(const TradeMap& map, std::size_t row);
/// The map's cost axis: the median step time (ms), or NaN for a failed row or an FEM row.
double stepCost(const TradeMap& map, std::size_t row);
/// The liver poke's axes: the largest |error| (%) over its depths, and its median step (ms);
/// NaN where the row has none (no liver poke, a failed one, or step times taken on another
/// thread count).
double worstOrganError(const TradeMap& map, std::size_t row);
double organStepCost(const TradeMap& map, std::size_t row);

std::string tradeCsv(const TradeMap& map);
std::string tradeMarkdown(const TradeMap& map);
/// Renders the map to a PNG at `path`. @throws CommandError when it cannot be written.
void writeTradePlot(const TradeMap& map, const std::string& path);
/// Renders the liver poke's map (worstOrganError against organStepCost) to a PNG at `path`.
/// @throws CommandError when it cannot be written.
void writeLiverTradePlot(const TradeMap& map, const std::string& path);

}  // namespace tissuesim::app
