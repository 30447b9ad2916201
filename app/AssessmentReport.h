// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session's assessment (sim/SessionAssessment.h) as the reports and the window give it: JSON
// (the `assessment` object of run's and replay's reports, the window's saved summary) and lines
// of text (the window's End session dialog).

#include <string>

#include <nlohmann/json.hpp>

#include "sim/SessionAssessment.h"

namespace tissuesim::app {

/// Units in the names: seconds, millimetres, newtons, cubic centimetres, per cent.
nlohmann::json assessmentJson(const AssessmentSummary& summary);

/// One figure a line, for a person.
std::string assessmentText(const AssessmentSummary& summary);

}  // namespace tissuesim::app
