// SPDX-License-Identifier: Apache-2.0
#include "app/CurveCsv.h"

#include <cstdio>
#include <iostream>
#include <sstream>

#include "app/CommandError.h"
#include "app/OutputFile.h"

namespace tissuesim::app {

void writeCurveCsv(std::ostream& out, const std::vector<CurveBranch>& branches) {
  constexpr double kPaPerKpa = 1000.0;
  out << "cycle,phase,lambda,stress_kpa\n";
  char line[128];
  for (const CurveBranch& branch : branches) {
    for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
      std::snprintf(line, sizeof line, "%d,%s,%.9g,%.9g\n", branch.cycle, phaseName(branch.phase),
                    branch.stretch[i], branch.stress_Pa[i] / kPaPerKpa);
      out << line;
    }
  }
}

void writeCurveCsv(const std::string& path, const std::vector<CurveBranch>& branches) {
  if (path.empty()) {
    writeCurveCsv(std::cout, branches);
    return;
  }
  std::ostringstream text;
  writeCurveCsv(text, branches);
  writeTextFile(path, "--output", text.str());
}

}  // namespace tissuesim::app
