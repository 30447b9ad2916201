// SPDX-License-Identifier: Apache-2.0
#include "analysis/UniaxialModel.h"

#include <array>
#include <utility>

namespace tissuesim {
namespace {
constexpr std::array<std::pair<UniaxialModel, std::string_view>, 5> kNames = {{
    {UniaxialModel::Sedf, "sedf"},
    {UniaxialModel::Eesm, "eesm"},
    {UniaxialModel::EesmPaper, "eesm-paper"},
    {UniaxialModel::Smm, "smm"},
    {UniaxialModel::Fem, "fem"},
}};
}  // namespace

std::optional<UniaxialModel> parseUniaxialModel(std::string_view name) {
  for (const auto& [model, text] : kNames) {
    if (text == name) return model;
  }
  return std::nullopt;
}

std::string_view modelName(UniaxialModel model) {
  for (const auto& [candidate, text] : kNames) {
    if (candidate == model) return text;
  }
  return "unknown";
}

std::string modelNames() {
  std::string names;
  for (const auto& entry : kNames) {
    if (!names.empty()) names += ", ";
    names += entry.second;
  }
  return names;
}

}  // namespace tissuesim
