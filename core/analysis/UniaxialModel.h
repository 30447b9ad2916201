// SPDX-License-Identifier: Apache-2.0
#pragma once
// The force laws compared in uniaxial tests (docs/model.md, "The spring network").

#include <optional>
#include <string>
#include <string_view>

namespace tissuesim {

enum class UniaxialModel {
  Sedf,       ///< the continuum closed form P = dW_T/dlambda with softening (the reference)
  Eesm,       ///< one energy-consistent EESM spring through the precomputed tables
  EesmPaper,  ///< the published secant force F = k_s(lambda) lambda, over v_ij
  Smm,        ///< a linear spring, one constant stiffness fitted to the sedf curve (Eq. 1)
  /// the FEM's material point (fem/IsochoricSoftening.h): the continuum's virgin stress times
  /// F at the point's peak I1bar, with the spring law's rounded onset and no residual strain
  Fem,
};

/// "sedf", "eesm", "eesm-paper", "smm" or "fem"; nullopt for anything else.
std::optional<UniaxialModel> parseUniaxialModel(std::string_view name);
std::string_view modelName(UniaxialModel model);
/// The accepted names, comma-separated, for messages.
std::string modelNames();

}  // namespace tissuesim
