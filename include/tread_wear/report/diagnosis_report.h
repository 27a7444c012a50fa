#pragma once
/// @file diagnosis_report.h
/// Writing a diagnosis: DIR/diagnosis.json (machine-readable verdict), DIR/report.md (for a person),
/// DIR/residuals.csv (per-run residuals before and after against every covariate; the plotting script
/// scripts/plot_diagnosis.py turns it into PNGs). Formats: docs/diagnosis.md.

#include <string>

#include <nlohmann/json.hpp>

#include "tread_wear/diagnosis/conceal.h"
#include "tread_wear/diagnosis/detectability.h"
#include "tread_wear/diagnosis/diagnosis.h"

namespace tread_wear {
namespace diagnosis {

/// The verdict and its evidence as JSON (keys: docs/diagnosis.md).
nlohmann::json diagnosisJson(const DiagnosisResult& result, const DiagnosisData& data);
/// The human-readable report (Markdown). `plots` lists PNG file names to embed (may be empty).
std::string diagnosisMarkdown(const DiagnosisResult& result, const DiagnosisData& data, const std::string& source,
                              const std::vector<std::string>& plots);
/// A detectability reference (detectability.h) as JSON: lambda, power, expected_right, terms_tried, verdicts
/// (share per verdict) and parameters (value, std_error); NaN as null.
nlohmann::json detectabilityJson(const Detectability& reference);
/// The answer as JSON.
nlohmann::json answerJson(const ConcealAnswer& answer);
/// Per-run residuals before/after and the covariates, as CSV text.
std::string residualsCsv(const DiagnosisResult& result, const DiagnosisData& data);

}  // namespace diagnosis
}  // namespace tread_wear
