// SPDX-License-Identifier: Apache-2.0
#include "analysis/TensileTestData.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace tissuesim {

namespace {

enum class Layout { Branches, StretchStress, DisplacementForce };

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) cells.push_back(trimmed(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

struct Reader {
  std::string name;
  int line = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw TestDataError(name + ":" + std::to_string(line) + ": " + what);
  }

  double number(const std::string& cell, const char* column) const {
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || errno == ERANGE) {
      fail("'" + cell + "' in column " + column + " is not a number");
    }
    if (!std::isfinite(value)) fail("column " + std::string(column) + " is not a finite number");
    return value;
  }
};

/// Cuts one measured sequence into loading and unloading branches where the stretch turns.
std::vector<CurveBranch> branchesOf(const std::vector<double>& stretch,
                                    const std::vector<double>& stress_Pa) {
  std::vector<CurveBranch> branches;
  int cycle = 0;
  for (std::size_t i = 0; i < stretch.size(); ++i) {
    // A point's phase is how it was reached (the first point's, where the test goes next): a
    // peak ends its loading branch.
    const bool isRising =
        i > 0 ? stretch[i] >= stretch[i - 1] : stretch.size() < 2 || stretch[1] >= stretch[0];
    const LoadPhase phase = isRising ? LoadPhase::Loading : LoadPhase::Unloading;
    if (branches.empty() || branches.back().phase != phase) {
      if (phase == LoadPhase::Loading || branches.empty()) ++cycle;
      CurveBranch branch;
      branch.cycle = cycle;
      branch.phase = phase;
      // The turning point belongs to both branches, as the simulator's curves have it.
      if (!branches.empty()) {
        branch.stretch.push_back(branches.back().stretch.back());
        branch.stress_Pa.push_back(branches.back().stress_Pa.back());
      }
      branches.push_back(std::move(branch));
    }
    branches.back().stretch.push_back(stretch[i]);
    branches.back().stress_Pa.push_back(stress_Pa[i]);
  }
  return branches;
}

}  // namespace

std::vector<CurveBranch> readTensileTestCsv(const std::filesystem::path& path,
                                            const std::optional<SpecimenGeometry>& specimen) {
  Reader reader{path.string()};
  std::ifstream in(path);
  if (!in) throw TestDataError(reader.name + ": cannot open the test data (missing or unreadable)");
  std::string text;
  std::string header;
  while (std::getline(in, text)) {
    ++reader.line;
    header = trimmed(text);
    if (!header.empty() && header[0] != '#') break;
    header.clear();
  }
  if (header.empty()) throw TestDataError(reader.name + ": the file is empty (no header, no data)");

  Layout layout;
  if (header == "cycle,phase,lambda,stress_kpa") {
    layout = Layout::Branches;
  } else if (header == "lambda,stress_kpa" || header == "stretch,stress_kpa") {
    layout = Layout::StretchStress;
  } else if (header == "displacement_mm,force_n") {
    layout = Layout::DisplacementForce;
    if (!specimen || !(specimen->gaugeLength_mm > 0.0) || !(specimen->crossSection_mm2 > 0.0)) {
      throw TestDataError(reader.name +
                          ": displacement and force need the specimen's gauge length and "
                          "cross-section (--length-mm, --area-mm2)");
    }
  } else {
    reader.fail("header '" + header +
                "' is not one of: cycle,phase,lambda,stress_kpa; lambda,stress_kpa; "
                "displacement_mm,force_n");
  }
  const std::size_t columns = splitCells(header).size();

  std::vector<CurveBranch> branches;
  std::vector<double> stretch, stress_Pa;
  while (std::getline(in, text)) {
    ++reader.line;
    const std::string row = trimmed(text);
    if (row.empty() || row[0] == '#') continue;
    const std::vector<std::string> cells = splitCells(row);
    if (cells.size() != columns) {
      reader.fail(std::to_string(cells.size()) + " values where the header names " +
                  std::to_string(columns));
    }
    double lambda = 0.0, stress = 0.0;
    if (layout == Layout::DisplacementForce) {
      lambda = 1.0 + reader.number(cells[0], "displacement_mm") / specimen->gaugeLength_mm;
      stress = reader.number(cells[1], "force_n") / (specimen->crossSection_mm2 * 1e-6);
    } else {
      const std::size_t at = layout == Layout::Branches ? 2 : 0;
      lambda = reader.number(cells[at], "lambda");
      stress = 1000.0 * reader.number(cells[at + 1], "stress_kpa");
    }
    if (!(lambda > 0.0)) reader.fail("a stretch of " + std::to_string(lambda) + " is not positive");
    if (layout != Layout::Branches) {
      stretch.push_back(lambda);
      stress_Pa.push_back(stress);
      continue;
    }
    const double cycleValue = reader.number(cells[0], "cycle");
    // Checked before the conversion: a double beyond int's range has no int value.
    if (!(cycleValue >= 1.0 && cycleValue <= 1e6) || cycleValue != std::floor(cycleValue)) {
      reader.fail("cycle '" + cells[0] + "' is not 1, 2, ... (at most 10^6)");
    }
    const int cycle = static_cast<int>(cycleValue);
    if (cells[1] != "loading" && cells[1] != "unloading") {
      reader.fail("phase '" + cells[1] + "' is neither loading nor unloading");
    }
    const LoadPhase phase = cells[1] == "loading" ? LoadPhase::Loading : LoadPhase::Unloading;
    if (branches.empty() || branches.back().cycle != cycle || branches.back().phase != phase) {
      branches.push_back({cycle, phase, {}, {}});
    } else {
      const double previous = branches.back().stretch.back();
      if (phase == LoadPhase::Loading && lambda < previous) {
        reader.fail("the loading branch of cycle " + std::to_string(cycle) + " falls from " +
                    std::to_string(previous) + " to " + std::to_string(lambda));
      }
      if (phase == LoadPhase::Unloading && lambda > previous) {
        reader.fail("the unloading branch of cycle " + std::to_string(cycle) + " rises from " +
                    std::to_string(previous) + " to " + std::to_string(lambda));
      }
    }
    branches.back().stretch.push_back(lambda);
    branches.back().stress_Pa.push_back(stress);
  }
  if (layout != Layout::Branches) branches = branchesOf(stretch, stress_Pa);
  if (branches.empty()) throw TestDataError(reader.name + ": a header but no data rows");
  return branches;
}

}  // namespace tissuesim
