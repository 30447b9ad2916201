// SPDX-License-Identifier: Apache-2.0
#pragma once
// A tissue file loaded with what every curve command builds from it: its strain energy, its
// stiffness tables, and the continuum test that validates a cyclic protocol against it.

#include <string>

#include "analysis/UniaxialExperiment.h"
#include "app/CommandError.h"
#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/TissueFile.h"

namespace tissuesim::app {

struct LoadedTissue {
  explicit LoadedTissue(const std::string& tissuePath)
      : path(tissuePath),
        parameters(loadTissueFile(tissuePath)),
        energy(parameters),
        table(energy),
        continuum(energy, table) {}

  /// @throws CommandError with one line naming the tissue when the protocol does not fit it.
  void validate(const UniaxialProtocol& protocol) const {
    try {
      continuum.validate(protocol);
    } catch (const std::invalid_argument& error) {
      throw CommandError(std::string(error.what()) + " (tissue " + path + ")");
    }
  }

  std::string path;
  TissueParameters parameters;
  StrainEnergy energy;
  StiffnessTable table;
  UniaxialExperiment continuum;
};

}  // namespace tissuesim::app
