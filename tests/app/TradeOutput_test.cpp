// SPDX-License-Identifier: Apache-2.0
// What `trade` writes, from a map whose figures are given: every CSV row has the header's
// fields, the Pareto column marks exactly the rows nothing beats on both axes, a failed row and
// the FEM reference's rows stay off the cost axis (the FEM on the lattice is on it, without a
// tensile fit), and the Markdown lists the front in increasing cost.

#include "app/trade/TradeOutput.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace tissuesim::app {
namespace {

/// The fields of one CSV line, quotes honoured.
std::vector<std::string> fieldsOf(const std::string& line) {
  std::vector<std::string> fields(1);
  bool isQuoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"') {
      if (isQuoted && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else {
        isQuoted = !isQuoted;
      }
    } else if (c == ',' && !isQuoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

/// The index of the header's column `name` (0 when it has none, which the tests reject: 0 is
/// the knob's).
std::size_t columnOf(const std::vector<std::string>& header, const std::string& name) {
  const auto found = std::find(header.begin(), header.end(), name);
  return found == header.end() ? 0 : static_cast<std::size_t>(found - header.begin());
}

/// tradeCsv's header and rows, each row checked to have the header's field count.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t column(const std::string& name) const { return columnOf(header, name); }
};

CsvTable csvOf(const TradeMap& map) {
  CsvTable table;
  std::istringstream csv(tradeCsv(map));
  std::string line;
  if (!std::getline(csv, line)) {
    ADD_FAILURE() << "no header";
    return table;
  }
  table.header = fieldsOf(line);
  while (std::getline(csv, line)) {
    table.rows.push_back(fieldsOf(line));
    EXPECT_EQ(table.rows.back().size(), table.header.size()) << line;
  }
  return table;
}

/// That `md` has each of `lines` after `heading`, in that order.
void expectListedInOrder(const std::string& md, const std::string& heading,
                         const std::vector<std::string>& lines) {
  std::size_t at = md.find(heading);
  ASSERT_NE(at, std::string::npos) << md;
  for (const std::string& line : lines) {
    const std::size_t found = md.find(line, at);
    ASSERT_NE(found, std::string::npos) << line << " after " << heading << " in\n" << md;
    at = found;
  }
}

TradeMap sampleMap() {
  TradeMap map;
  map.settings.depths_m = {0.001, 0.002};
  map.reference.force_N = {0.1, 0.4};
  map.reference.surfaceDisplacement_m = {Eigen::Vector3d::Zero()};
  const auto spring = [&](const std::string& name, double median_ms, std::vector<double> pace,
                          const std::string& failure = "") {
    TradeRow row;
    row.knob = "resolution";
    row.name = name;
    TradeMeasurement m;
    m.cost.springs = 1000;
    m.cost.stepMedian_ms = median_ms;
    m.staticForce_N = {0.1, 0.4};
    m.paceForce_N = std::move(pace);
    m.failure = failure;
    map.rows.push_back(row);
    map.measurements.push_back(m);
    map.cellEdges_m.push_back(0.01);
  };
  spring("fast, poor", 0.1, {0.2, 0.8});                    // 100 %: on the front
  spring("slow, good", 2.0, {0.11, 0.42});                  // 10 %: on the front
  spring("slower and worse", 3.0, {0.15, 0.5});             // 50 %: beaten by "slow, good"
  spring("a name, with \"quotes\"", 0.5, {0.13, 0.44});     // 30 %: on the front
  spring("failed", 0.01, {0.1, 0.4}, "liver run: killed");  // no cost: off the map
  TradeRow tets;
  tets.knob = "fem-tets";
  tets.model = "fem";
  tets.name = "fem on the lattice";
  TradeMeasurement tetsMeasurement;
  tetsMeasurement.cost.springs = 1000;
  tetsMeasurement.cost.stepMedian_ms = 1.5;
  tetsMeasurement.staticForce_N = {0.15, 0.6};
  tetsMeasurement.paceForce_N = {0.15, 0.6};  // 50 %: beaten by "a name"
  tetsMeasurement.tensileLoadingR2 = 0.5;     // against the virgin curve
  tetsMeasurement.tensileUnloadingR2 = 0.25;  // no softening: never shown
  map.rows.push_back(tets);
  map.measurements.push_back(tetsMeasurement);
  map.cellEdges_m.push_back(0.01);
  TradeRow fem;
  fem.knob = "reference";
  fem.name = "fem, refinement 1";
  fem.femRefinement = 1;
  TradeMeasurement femMeasurement;
  femMeasurement.cost.stepMedian_ms = 5000.0;
  femMeasurement.staticForce_N = {0.099, 0.41};
  map.rows.push_back(fem);
  map.measurements.push_back(femMeasurement);
  map.cellEdges_m.push_back(0.0);
  return map;
}

TEST(TradeOutput, EveryCsvRowHasTheHeadersFieldsAndTheFrontIsMarked) {
  const TradeMap map = sampleMap();
  std::istringstream csv(tradeCsv(map));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = fieldsOf(line);
  const std::size_t pareto = columnOf(header, "pareto");
  const std::size_t name = columnOf(header, "name");
  ASSERT_GT(pareto, 0u);
  ASSERT_GT(name, 0u);
  std::vector<std::string> onFront;
  int rows = 0;
  while (std::getline(csv, line)) {
    const std::vector<std::string> fields = fieldsOf(line);
    ASSERT_EQ(fields.size(), header.size()) << line;
    if (fields[pareto] == "1") onFront.push_back(fields[name]);
    ++rows;
  }
  EXPECT_EQ(rows, 7);
  // In the rows' order.
  EXPECT_EQ(onFront,
            (std::vector<std::string>{"fast, poor", "slow, good", "a name, with \"quotes\""}));
}

TEST(TradeOutput, TheAxesLeaveOutFailedAndFemRows) {
  const TradeMap map = sampleMap();
  EXPECT_DOUBLE_EQ(worstError(map, 0), 100.0);
  EXPECT_NEAR(worstError(map, 1), 10.0, 1e-9);
  EXPECT_TRUE(std::isnan(stepCost(map, 4)));  // failed
  EXPECT_TRUE(std::isnan(worstError(map, 4)));
  EXPECT_NEAR(stepCost(map, 5), 1.5, 1e-12);  // the lattice's FEM: a real-time step
  EXPECT_NEAR(worstError(map, 5), 50.0, 1e-9);
  EXPECT_TRUE(std::isnan(stepCost(map, 6)));   // FEM: not a real-time step
  EXPECT_NEAR(worstError(map, 6), 2.5, 1e-9);  // its static error
}

TEST(TradeOutput, TheLatticeFemRowHasItsLoadingFitAndNoUnloadingOne) {
  // The tets have no softening: their row shows its loading R^2 (against the virgin curve) and
  // leaves the unloading one empty; the FEM reference's row has neither.
  const TradeMap map = sampleMap();
  std::istringstream csv(tradeCsv(map));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = fieldsOf(line);
  const std::size_t loading = columnOf(header, "tensile_r2_loading");
  const std::size_t unloading = columnOf(header, "tensile_r2_unloading");
  ASSERT_GT(loading, 0u);
  std::vector<std::vector<std::string>> shown;
  while (std::getline(csv, line)) shown.push_back(fieldsOf(line));
  ASSERT_EQ(shown.size(), 7u);
  EXPECT_EQ(shown[0][loading], "0.000000");  // a spring row's, measured (0 in this sample)
  EXPECT_EQ(shown[0][unloading], "0.000000");
  EXPECT_EQ(shown[5][loading], "0.500000");
  EXPECT_EQ(shown[5][unloading], "");
  EXPECT_EQ(shown[6][loading], "");
  EXPECT_EQ(shown[6][unloading], "");
  const std::string md = tradeMarkdown(map);
  const std::size_t row = md.find("| fem on the lattice | 1000 |");
  ASSERT_NE(row, std::string::npos) << md;
  const std::string text = md.substr(row, md.find('\n', row) - row);
  EXPECT_NE(text.find("| 50.00 / - (virgin; no softening) |"), std::string::npos) << text;
}

TEST(TradeOutput, TheMarkdownListsTheFrontInIncreasingCost) {
  const std::string md = tradeMarkdown(sampleMap());
  expectListedInOrder(md, "## The Pareto front",
                      {"- fast, poor: 0.100 ms, 100 %", "- a name, with \"quotes\": 0.500 ms, 30 %",
                       "- slow, good: 2.000 ms, 10 % (over the 1 ms budget)"});
  EXPECT_NE(md.find("| failed | failed: liver run: killed"), std::string::npos);
}

TEST(TradeOutput, TheLiverPokeHasItsColumnsWhereItsReferenceIsAtHand) {
  TradeMap map = sampleMap();
  // Without a reference: no liver columns, and the note says why.
  map.organNote = "liver-fem-poke.csv has no reference for this scene";
  {
    std::istringstream csv(tradeCsv(map));
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line.find("organ_"), std::string::npos) << line;
    const std::string md = tradeMarkdown(map);
    EXPECT_NE(md.find("No liver poke: liver-fem-poke.csv has no reference"), std::string::npos);
    EXPECT_EQ(md.find("liver poke error"), std::string::npos);
  }
  map.organNote.clear();
  map.settings.organDepths_m = {0.001, 0.004};
  map.organReference_N = {0.02, 0.2};
  map.measurements[0].organForce_N = {0.03, 0.18};  // +50 %, -10 %
  map.measurements[0].organEvents = 2;
  map.measurements[2].organForce_N = {0.02, 0.2};
  map.measurements[2].organEvents = 1;
  map.measurements[1].organFailure = "the simulator did not reach 4 mm";
  const CsvTable csv = csvOf(map);
  const std::size_t force = csv.column("organ_force_4mm_n");
  const std::size_t error = csv.column("organ_error_1mm_percent");
  const std::size_t events = csv.column("organ_events");
  const std::size_t failure = csv.column("organ_failure");
  ASSERT_GT(force, 0u);
  ASSERT_GT(error, 0u);
  ASSERT_GT(events, 0u);
  ASSERT_GT(failure, 0u);
  const std::vector<std::vector<std::string>>& shown = csv.rows;
  ASSERT_EQ(shown.size(), 7u);
  EXPECT_EQ(shown[0][force], "0.18");
  EXPECT_EQ(shown[0][error], "50.00");
  EXPECT_EQ(shown[0][events], "2");
  EXPECT_EQ(shown[1][error], "");
  EXPECT_EQ(shown[1][failure], "the simulator did not reach 4 mm");
  EXPECT_EQ(shown[6][force], "");  // the FEM's row has none
  const std::string md = tradeMarkdown(map);
  EXPECT_NE(md.find("0.02 / 0.2 N at 1 / 4 mm below the surface"), std::string::npos) << md;
  const std::size_t row = md.find("| fast, poor |");
  ASSERT_NE(row, std::string::npos);
  const std::string text = md.substr(row, md.find('\n', row) - row);
  EXPECT_NE(text.find("| +50 / -10 (2 events) |"), std::string::npos) << text;
  EXPECT_NE(md.find("| +0 / +0 (1 event) |"), std::string::npos) << md;
  EXPECT_NE(md.find("failed: the simulator did not reach 4 mm |"), std::string::npos);
  // Every table row has as many cells as the header.
  const std::size_t table = md.find("| setting |");
  const auto cells = [](const std::string& tableRow) {
    return std::count(tableRow.begin(), tableRow.end(), '|');
  };
  const std::string headerRow = md.substr(table, md.find('\n', table) - table);
  for (std::size_t at = md.find("\n|", table);
       at != std::string::npos && at < md.find("\n\n", table); at = md.find("\n|", at + 1)) {
    const std::string next = md.substr(at + 1, md.find('\n', at + 1) - at - 1);
    if (next.rfind("|---", 0) == 0) continue;
    EXPECT_EQ(cells(next), cells(headerRow)) << next;
  }
}

/// The Markdown table's line for the setting `name`; "" (and a failure) when it has none.
std::string markdownRow(const std::string& md, const std::string& name) {
  const std::size_t at = md.find("| " + name + " |");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no row " << name << " in\n" << md;
    return "";
  }
  return md.substr(at, md.find('\n', at) - at);
}

/// That `line` has as many cells as the Markdown table's header.
void expectHeadersCellCount(const std::string& md, const std::string& line) {
  const std::size_t table = md.find("| setting |");
  const std::string header = md.substr(table, md.find('\n', table) - table);
  EXPECT_EQ(std::count(line.begin(), line.end(), '|'),
            std::count(header.begin(), header.end(), '|'))
      << line;
}

/// An FEM row on the organ's mesh "graded.msh".
TradeRow graded(const std::string& knob, const std::string& name) {
  TradeRow row;
  row.knob = knob;
  row.model = "fem";
  row.organMeshPath = "graded.msh";
  row.organMeshLabel = "graded";
  row.name = name;
  return row;
}

/// Appends a row on an organ's mesh (no lattice, so no cell edge); its index.
std::size_t appendOrganRow(TradeMap& map, const TradeRow& row, const TradeMeasurement& measured) {
  map.rows.push_back(row);
  map.measurements.push_back(measured);
  map.cellEdges_m.push_back(0.0);
  return map.rows.size() - 1;
}

TEST(TradeOutput, TheFemOnTheOrgansMeshIsOnTheLiverPokesAxesAlone) {
  TradeMap map = sampleMap();
  map.settings.organDepths_m = {0.001, 0.004};
  map.organReference_N = {0.02, 0.2};
  map.measurements[0].organForce_N = {0.03, 0.18};  // 50 % at 0.1 ms: on the liver's front
  map.measurements[0].organStepMedian_ms = 0.1;
  map.measurements[2].organForce_N = {0.024, 0.2};  // 20 % at 3 ms: on it
  map.measurements[2].organStepMedian_ms = 3.0;
  map.measurements[3].organForce_N = {0.02, 0.25};  // 25 % at 4 ms: beaten by row 2
  map.measurements[3].organStepMedian_ms = 4.0;
  map.measurements[1].organForce_N = {0.02, 0.2};  // 0 %, but timed on another thread count
  map.measurements[1].organStepMedian_ms = std::numeric_limits<double>::quiet_NaN();
  TradeRow organ = graded("fem-organ", "fem per face on graded");
  organ.strainCells = "faces";
  TradeMeasurement organMeasurement;
  organMeasurement.cost.nodes = 965;
  organMeasurement.cost.stepMedian_ms = 11.0;
  organMeasurement.cost.stepP99_ms = 13.0;
  organMeasurement.organForce_N = {0.021, 0.19};  // 5 % at 11 ms: on it
  organMeasurement.organStepMedian_ms = 11.0;
  organMeasurement.organStepP99_ms = 13.0;
  const std::size_t organRow = appendOrganRow(map, organ, organMeasurement);

  // On the liver's axes, not on the block's.
  EXPECT_TRUE(std::isnan(worstError(map, organRow)));
  EXPECT_NEAR(worstOrganError(map, organRow), 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(organStepCost(map, organRow), 11.0);
  EXPECT_TRUE(std::isnan(organStepCost(map, 1)));
  EXPECT_NEAR(worstOrganError(map, 2), 20.0, 1e-9);

  const CsvTable csv = csvOf(map);
  const std::size_t organPareto = csv.column("organ_pareto");
  const std::size_t pareto = csv.column("pareto");
  const std::size_t name = csv.column("name");
  const std::size_t median = csv.column("organ_step_median_ms");
  const std::size_t law = csv.column("law");
  const std::size_t cells = csv.column("strain_cells");
  ASSERT_GT(organPareto, 0u);
  ASSERT_GT(median, 0u);
  ASSERT_GT(cells, 0u);
  std::vector<std::string> onOrganFront;
  std::vector<std::string> organFields;
  for (const std::vector<std::string>& fields : csv.rows) {
    if (fields[organPareto] == "1") onOrganFront.push_back(fields[name]);
    if (fields[name] == organ.name) organFields = fields;
  }
  EXPECT_EQ(onOrganFront, (std::vector<std::string>{"fast, poor", "slower and worse", organ.name}));
  ASSERT_FALSE(organFields.empty());
  EXPECT_EQ(organFields[pareto], "0");
  EXPECT_EQ(organFields[median], "11.0000");
  EXPECT_EQ(organFields[law], "fem-organ");
  EXPECT_EQ(organFields[cells], "faces");

  const std::string md = tradeMarkdown(map);
  const std::string text = markdownRow(md, "fem per face on graded");
  EXPECT_NE(text.find("| - (965 nodes) | - | 11.000 / 13.000 (liver poke) |"), std::string::npos)
      << text;
  EXPECT_NE(text.find("| +5 / -5 |"), std::string::npos) << text;
  expectListedInOrder(md, "## The Pareto front on the liver poke",
                      {"- fast, poor: 0.100 ms, 50 %", "- slower and worse: 3.000 ms, 20 % (over",
                       "- fem per face on graded: 11.000 ms, 5 % (over"});
  expectHeadersCellCount(md, text);
}

TEST(TradeOutput, TheReferencesElementOnTheOrgansMeshIsAStaticRowOfTheLiverPoke) {
  TradeMap map = sampleMap();
  map.settings.organDepths_m = {0.001, 0.004};
  map.organReference_N = {0.02, 0.2};
  TradeRow quadratic = graded("fem-quadratic", "fem quadratic tets on graded");
  quadratic.element = "quadratic";
  quadratic.strainCells.clear();
  quadratic.integrator = "static";
  TradeMeasurement measured;
  measured.cost.nodes = 6210;
  measured.cost.stepMedian_ms = 250.0;
  measured.cost.stepP99_ms = std::numeric_limits<double>::quiet_NaN();
  measured.cost.stepsPerSecond = 4.0;
  measured.cost.events = 1;
  measured.organForce_N = {0.019, 0.21};  // -5 / +5 %
  measured.organEvents = 1;
  measured.organStepMedian_ms = 250.0;
  measured.organStepP99_ms = std::numeric_limits<double>::quiet_NaN();
  measured.organStepsPerSecond = 4.0;
  const std::size_t row = appendOrganRow(map, quadratic, measured);

  EXPECT_TRUE(std::isnan(worstError(map, row)));
  EXPECT_NEAR(worstOrganError(map, row), 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(organStepCost(map, row), 250.0);

  const CsvTable csv = csvOf(map);
  const std::size_t name = csv.column("name");
  const std::size_t law = csv.column("law");
  const std::size_t integrator = csv.column("integrator");
  const std::size_t events = csv.column("organ_events");
  ASSERT_GT(law, 0u);
  ASSERT_GT(events, 0u);
  std::vector<std::string> fields;
  for (const std::vector<std::string>& candidate : csv.rows) {
    if (candidate[name] == quadratic.name) fields = candidate;
  }
  ASSERT_FALSE(fields.empty());
  EXPECT_EQ(fields[law], "fem-quadratic");
  EXPECT_EQ(fields[integrator], "static");
  EXPECT_EQ(fields[events], "1");

  const std::string md = tradeMarkdown(map);
  const std::string text = markdownRow(md, "fem quadratic tets on graded");
  EXPECT_NE(
      text.find("| - (6210 nodes) | - | 250.000 a Newton iteration (liver poke, static) | 4 |"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("| -5 / +5 (1 unconverged solve) |"), std::string::npos) << text;
  expectHeadersCellCount(md, text);
}

TEST(TradeOutput, TheFemSceneAtItsOwnRateIsTimedByItsStepOnTheLiverAndTheBlock) {
  TradeMap map = sampleMap();
  map.settings.organDepths_m = {0.001, 0.004};
  map.organReference_N = {0.02, 0.2};
  TradeRow row = graded("fem-haptic-rate", "fem at its own rate on graded");
  row.element = "haptic-rate";
  row.strainCells.clear();
  row.integrator = "haptic-rate";
  TradeMeasurement measured;
  measured.cost.nodes = 1313;
  measured.cost.stepMedian_ms = 0.1;
  measured.cost.stepP99_ms = 0.5;
  measured.cost.stepsPerSecond = 9000.0;
  measured.cost.events = 3;
  measured.organForce_N = {0.021, 0.19};  // +5 / -5 %
  measured.organEvents = 3;
  measured.organStepMedian_ms = 0.1;
  measured.organStepP99_ms = 0.5;
  measured.organStepsPerSecond = 9000.0;
  measured.organUpdateMean_ms = 116.0;
  measured.staticForce_N = {0.102, 0.388};  // the block at the poke's speed: +2 / -3 %
  const std::size_t index = appendOrganRow(map, row, measured);

  // On both maps: its block error from its static column, its step the scene's.
  EXPECT_NEAR(worstError(map, index), 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(stepCost(map, index), 0.1);
  EXPECT_NEAR(worstOrganError(map, index), 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(organStepCost(map, index), 0.1);

  const CsvTable csv = csvOf(map);
  const std::size_t name = csv.column("name");
  const std::size_t law = csv.column("law");
  const std::size_t organPareto = csv.column("organ_pareto");
  ASSERT_GT(law, 0u);
  std::vector<std::string> fields;
  for (const std::vector<std::string>& candidate : csv.rows) {
    if (candidate[name] == row.name) fields = candidate;
  }
  ASSERT_FALSE(fields.empty());
  EXPECT_EQ(fields[law], "fem-haptic-rate");
  EXPECT_EQ(fields[organPareto], "1");  // 5 % at 0.1 ms: nothing beats it
  EXPECT_EQ(fields[csv.column("error_static_2mm_percent")], "-3.00");
  EXPECT_EQ(fields[csv.column("pareto")], "1");  // 3 % at 0.1 ms on the block

  const std::string md = tradeMarkdown(map);
  const std::string text = markdownRow(md, "fem at its own rate on graded");
  EXPECT_NE(text.find("| - (1313 nodes) | - | 0.100 / 0.500 (liver poke, the contact's step; an "
                      "FEM update 116 ms) | 9000 |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("| +2 / -3 (at the poke's speed) | - |"), std::string::npos) << text;
  EXPECT_NE(text.find("| +5 / -5 (3 events) |"), std::string::npos) << text;
  expectHeadersCellCount(md, text);
}

}  // namespace
}  // namespace tissuesim::app
