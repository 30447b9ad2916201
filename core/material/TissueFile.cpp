// SPDX-License-Identifier: Apache-2.0
#include "material/TissueFile.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

namespace tissuesim {
namespace {

using Json = nlohmann::json;

constexpr double kPaToPa = 1000.0;  // the file gives moduli in kPa; the engine works in Pa

/// Lower bound of a numeric field: value > bound (strict) or value >= bound.
struct Bound {
  double value;
  bool isStrict;
};

/// One numeric field of the schema.
struct NumberField {
  const char* key;
  const char* meaning;  // what it is and its unit, for messages
  bool isRequired;
  Bound lower;
  double upper;  // inclusive; +inf when unbounded
};

// The schema of docs/tissue-file.md. Required parameters have no default: a tissue without
// its fitted constants is not a tissue. The upper bounds keep every derived quantity finite and
// are far outside any soft tissue: moduli up to 1 GPa (kPa to a few MPa for organs; 1e308 kPa
// overflowed to infinity in Pa), 10^8 chain segments (Gaussian to machine precision over the
// tables' stretches), densities between a gas's and osmium's.
constexpr double kMaxModulus_kPa = 1e6;
const NumberField kNumberFields[] = {
    {"mu_kpa", "network shear modulus mu in kPa", true, {0.0, true}, kMaxModulus_kPa},
    {"N", "chain segments N (dimensionless)", true, {1.0, true}, 1e8},
    {"A1_kpa", "fibre modulus A1 in kPa", true, {0.0, false}, kMaxModulus_kPa},
    {"A2_kpa", "fibre modulus A2 in kPa", true, {0.0, false}, kMaxModulus_kPa},
    {"f", "fibre volume fraction f", true, {0.0, false}, 1.0},
    {"b", "softening parameter b (dimensionless)", true, {0.0, false}, 1e6},
    {"C_kpa", "residual-strain modulus C in kPa", true, {0.0, true}, kMaxModulus_kPa},
    {"v_ij_m2", "spring cross-section v_ij in m^2", true, {0.0, true}, 1.0},
    {"density_kg_m3", "mass density in kg/m^3", false, {1.0, false}, 1e5},
    {"damage_stretch", "damage stretch (dimensionless, above 1)", false, {1.0, true}, 10.0},
};
const char* const kStringFields[] = {"name", "source", "notes", "inverse_langevin"};
const char* const kIntegerFields[] = {"n"};

std::string allowedKeys() {
  std::string keys;
  for (const auto& field : kNumberFields) keys += std::string(keys.empty() ? "" : ", ") + field.key;
  for (const char* key : kIntegerFields) keys += std::string(", ") + key;
  for (const char* key : kStringFields) keys += std::string(", ") + key;
  return keys;
}

bool isKnownKey(const std::string& key) {
  for (const auto& field : kNumberFields) {
    if (key == field.key) return true;
  }
  for (const char* known : kIntegerFields) {
    if (key == known) return true;
  }
  for (const char* known : kStringFields) {
    if (key == known) return true;
  }
  return false;
}

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw TissueFileError(source + ": " + what);
}

std::string describeType(const Json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return std::string(value.type_name()) + " " + text;
}

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

/// JSON has no NaN or Infinity, and a literal like 1e999 overflows to infinity. Both would
/// otherwise surface as a parse error without the field's name, so look for them first.
void rejectNonFiniteLiterals(std::string_view text, const std::string& source) {
  const auto isSpace = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  const auto isBare = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '+' || c == '-' ||
           c == '_';
  };
  // Scan for "key" : bareword, the only place a number can stand in a tissue file.
  std::size_t i = 0;
  while ((i = text.find('"', i)) != std::string_view::npos) {
    const std::size_t close = text.find('"', i + 1);
    if (close == std::string_view::npos) return;  // the JSON parser reports the open string
    const std::string key(text.substr(i + 1, close - i - 1));
    std::size_t j = close + 1;
    while (j < text.size() && isSpace(text[j])) ++j;
    i = close + 1;
    if (j >= text.size() || text[j] != ':') continue;
    ++j;
    while (j < text.size() && isSpace(text[j])) ++j;
    std::size_t end = j;
    while (end < text.size() && isBare(text[end])) ++end;
    if (end == j) continue;
    const std::string literal(text.substr(j, end - j));
    std::string lower = literal;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower == "true" || lower == "false" || lower == "null") continue;
    const bool isWordNonFinite =
        lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos;
    const bool isOverflow = !isWordNonFinite &&
                            std::isdigit(static_cast<unsigned char>(lower.back())) != 0 &&
                            !std::isfinite(std::strtod(literal.c_str(), nullptr));
    if (isWordNonFinite || isOverflow) {
      fail(source, "field '" + key + "' is " + literal +
                       ", which is not a finite number; expected a finite JSON number");
    }
  }
}

void lineAndColumn(std::string_view text, std::size_t byte, std::size_t& line,
                   std::size_t& column) {
  line = 1;
  column = 1;
  for (std::size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
}

double readNumber(const Json& root, const NumberField& field, double fallback,
                  const std::string& source) {
  const auto found = root.find(field.key);
  if (found == root.end()) {
    if (field.isRequired) {
      fail(source, std::string("missing field '") + field.key + "' (" + field.meaning + ")");
    }
    return fallback;
  }
  if (!found->is_number()) {
    fail(source, std::string("field '") + field.key + "' must be a number (" + field.meaning +
                     "), found " + describeType(*found));
  }
  const double value = found->get<double>();
  if (!std::isfinite(value)) {
    fail(source, std::string("field '") + field.key + "' is not finite; expected " + field.meaning);
  }
  const bool isBelow =
      field.lower.isStrict ? !(value > field.lower.value) : !(value >= field.lower.value);
  if (isBelow || value > field.upper) {
    std::string range =
        std::string(field.lower.isStrict ? "> " : ">= ") + formatNumber(field.lower.value);
    if (std::isfinite(field.upper)) range += " and <= " + formatNumber(field.upper);
    std::string why;
    if (std::string(field.key) == "N") {
      why =
          ": with N <= 1 the chains lock before the unstretched state (lambda_r = 1/sqrt(N) "
          ">= 1), so lambda = 1 is inadmissible";
    }
    fail(source, std::string("field '") + field.key + "' = " + formatNumber(value) +
                     " is out of range" + why + "; expected " + field.meaning + " " + range);
  }
  return value;
}

std::string readString(const Json& root, const char* key, const std::string& fallback,
                       const std::string& source) {
  const auto found = root.find(key);
  if (found == root.end()) return fallback;
  if (!found->is_string()) {
    fail(source,
         std::string("field '") + key + "' must be a string, found " + describeType(*found));
  }
  return found->get<std::string>();
}

}  // namespace

TissueParameters parseTissueJson(std::string_view text, const std::string& source) {
  if (std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c) != 0; })) {
    fail(source,
         "the file is empty; expected a JSON object of tissue parameters "
         "(see docs/tissue-file.md)");
  }
  // Control bytes other than whitespace never occur in a JSON text file.
  const bool isBinary = std::any_of(text.begin(), text.end(), [](unsigned char c) {
    return c < 0x20 && c != '\n' && c != '\r' && c != '\t';
  });
  if (isBinary)
    fail(source, "contains binary data; expected a JSON text file of tissue parameters");
  rejectNonFiniteLiterals(text, source);

  Json root;
  try {
    root = Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& error) {
    std::size_t line = 0;
    std::size_t column = 0;
    lineAndColumn(text, error.byte == 0 ? 0 : error.byte - 1, line, column);
    // nlohmann's text is "[json.exception...] parse error at line L, column C: WHAT; last read:
    // 'TEXT'": keep WHAT, which never echoes the file's bytes back to the terminal.
    std::string detail = error.what();
    if (const auto colon = detail.find(": "); colon != std::string::npos) {
      detail = detail.substr(colon + 2);
    }
    if (const auto lastRead = detail.find("; last read"); lastRead != std::string::npos) {
      detail = detail.substr(0, lastRead);
    }
    fail(source, "line " + std::to_string(line) + ", column " + std::to_string(column) +
                     ": not valid JSON (" + detail + ")");
  } catch (const Json::exception& error) {
    fail(source, std::string("not valid JSON (") + error.what() + ")");
  }
  if (!root.is_object()) {
    fail(source, std::string("expected a JSON object of tissue parameters at the top level, "
                             "found ") +
                     root.type_name());
  }

  for (const auto& item : root.items()) {
    // Unknown keys are errors: a misspelt parameter silently left at its default would
    // simulate a different tissue from the one the instructor wrote.
    if (!isKnownKey(item.key())) {
      fail(source, "unknown field '" + item.key() + "'; allowed fields: " + allowedKeys());
    }
  }

  TissueParameters params;
  params.name = readString(root, "name", "unnamed tissue", source);
  params.source = readString(root, "source", "", source);
  readString(root, "notes", "", source);

  const auto number = [&](const char* key, double fallback) {
    for (const auto& field : kNumberFields) {
      if (std::string(field.key) == key) return readNumber(root, field, fallback, source);
    }
    throw std::logic_error(std::string("tissue schema has no number field ") + key);
  };
  params.mu_Pa = number("mu_kpa", 0.0) * kPaToPa;
  params.chainSegmentsN = number("N", 0.0);
  params.A1_Pa = number("A1_kpa", 0.0) * kPaToPa;
  params.A2_Pa = number("A2_kpa", 0.0) * kPaToPa;
  params.fibreFraction = number("f", 0.0);
  params.softeningB = number("b", 0.0);
  params.softeningC_Pa = number("C_kpa", 0.0) * kPaToPa;
  params.springArea_m2 = number("v_ij_m2", 0.0);
  params.density_kg_m3 = number("density_kg_m3", 1060.0);
  params.damageStretch = number("damage_stretch", TissueParameters{}.damageStretch);

  if (const auto found = root.find("n"); found != root.end()) {
    if (!found->is_number_integer() && !found->is_number_unsigned()) {
      fail(source, "field 'n' must be the integer 1 or 2 (softening exponent of Eq. 17), found " +
                       describeType(*found));
    }
    const auto exponent = found->get<long long>();
    if (exponent != 1 && exponent != 2) {
      fail(source, "field 'n' = " + std::to_string(exponent) +
                       " is out of range; expected the softening exponent of Eq. 17, 1 or 2");
    }
    params.softeningExponentN = static_cast<int>(exponent);
  }

  const std::string langevin = readString(root, "inverse_langevin", "puso", source);
  if (langevin == "puso") {
    params.inverseLangevin = InverseLangevin::Puso;
  } else if (langevin == "exact") {
    params.inverseLangevin = InverseLangevin::Exact;
  } else {
    fail(source, "field 'inverse_langevin' = \"" + langevin + "\"; expected \"puso\" or \"exact\"");
  }
  return params;
}

TissueParameters loadTissueFile(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) fail(source, "is a directory, not a tissue file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(source, "cannot open the tissue file (missing or unreadable)");
  // A tissue file is a few hundred bytes; refuse anything absurd before reading it whole.
  constexpr std::uintmax_t kMaxBytes = 1 << 20;
  const auto size = std::filesystem::file_size(path, error);
  if (!error && size > kMaxBytes) {
    fail(source, "is " + std::to_string(size) + " bytes; a tissue file is expected under 1 MiB");
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parseTissueJson(buffer.str(), source);
}

std::string tissueFileText(const TissueParameters& parameters, const std::string& notes) {
  nlohmann::ordered_json root;
  root["name"] = parameters.name;
  root["source"] = parameters.source;
  if (!notes.empty()) root["notes"] = notes;
  root["mu_kpa"] = parameters.mu_Pa / kPaToPa;
  root["N"] = parameters.chainSegmentsN;
  root["A1_kpa"] = parameters.A1_Pa / kPaToPa;
  root["A2_kpa"] = parameters.A2_Pa / kPaToPa;
  root["f"] = parameters.fibreFraction;
  root["b"] = parameters.softeningB;
  root["C_kpa"] = parameters.softeningC_Pa / kPaToPa;
  root["n"] = parameters.softeningExponentN;
  root["v_ij_m2"] = parameters.springArea_m2;
  root["density_kg_m3"] = parameters.density_kg_m3;
  root["damage_stretch"] = parameters.damageStretch;
  root["inverse_langevin"] =
      parameters.inverseLangevin == InverseLangevin::Exact ? "exact" : "puso";
  return root.dump(2) + "\n";
}

}  // namespace tissuesim
