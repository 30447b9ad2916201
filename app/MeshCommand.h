// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim mesh`: a tet mesh from a surface (lattice cover), or a check and conversion of a
// tet mesh, with the quality figures either way.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerMeshCommand(CLI::App& app);

}  // namespace tissuesim::app
