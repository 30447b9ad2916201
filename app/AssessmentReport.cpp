// SPDX-License-Identifier: Apache-2.0
#include "app/AssessmentReport.h"

#include <cstdio>

namespace tissuesim::app {

nlohmann::json assessmentJson(const AssessmentSummary& summary) {
  nlohmann::json json;
  json["duration_s"] = summary.duration_s;
  json["tool_path_length_mm"] = summary.toolPathLength_m * 1e3;
  json["peak_tool_force_n"] = summary.peakToolForce_N;
  json["mean_contact_force_n"] = summary.meanContactForce_N;
  json["contact_time_s"] = summary.contactTime_s;
  json["force_threshold_n"] = summary.thresholds.toolForce_N;
  json["time_above_force_threshold_s"] = summary.aboveForceThreshold_s;
  json["largest_stretch"] = summary.largestStretch;
  json["damage_stretch"] = summary.thresholds.damageStretch;
  json["damaged_springs"] = summary.damagedSpringCount;
  json["damaged_volume_cm3"] = summary.damagedVolume_m3 * 1e6;
  json["damaged_volume_percent"] = summary.damagedFraction() * 100.0;
  return json;
}

std::string assessmentText(const AssessmentSummary& summary) {
  char text[1024];
  std::snprintf(text, sizeof text,
                "Duration: %.1f s\n"
                "Tool path: %.0f mm\n"
                "Peak force on the tool: %.2f N\n"
                "Mean force in contact: %.2f N over %.1f s of contact\n"
                "Time above %.3g N: %.2f s\n"
                "Largest stretch: %.3f\n"
                "Tissue stretched past %.3g: %.2f cm^3 (%.2f %% of the organ, %ld springs)\n",
                summary.duration_s, summary.toolPathLength_m * 1e3, summary.peakToolForce_N,
                summary.meanContactForce_N, summary.contactTime_s, summary.thresholds.toolForce_N,
                summary.aboveForceThreshold_s, summary.largestStretch,
                summary.thresholds.damageStretch, summary.damagedVolume_m3 * 1e6,
                summary.damagedFraction() * 100.0, summary.damagedSpringCount);
  return text;
}

}  // namespace tissuesim::app
