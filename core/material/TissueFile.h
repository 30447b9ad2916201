// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading and validating a tissue parameter file (JSON). The schema is in docs/tissue-file.md.
//
// Every error is a TissueFileError whose message names the file, the field (or the line and
// column for malformed JSON) and what was expected, in one line.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "material/TissueParameters.h"

namespace tissuesim {

class TissueFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads and validates a tissue file. Moduli in kPa in the file become Pa.
/// @throws TissueFileError naming the file and the offending field.
TissueParameters loadTissueFile(const std::filesystem::path& path);

/// The same from text already in memory; `sourceName` stands for the file in messages.
TissueParameters parseTissueJson(std::string_view text, const std::string& sourceName);

/// A tissue file's text for these parameters (every field, moduli in kPa, `notes` as given):
/// what parseTissueJson reads back to the same values.
std::string tissueFileText(const TissueParameters& parameters, const std::string& notes = "");

}  // namespace tissuesim
