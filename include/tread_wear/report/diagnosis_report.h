#pragma once
/// @file diagnosis_report.h
/// Writing a diagnosis: DIR/diagnosis.json (machine-readable verdict), DIR/report.md (for a person),
/// DIR/residuals.csv (per-run residuals before and after against every covariate; the plotting script
/// scripts/plot_diagnosis.py turns it into PNGs). Formats: docs/diagnosis.md.

#include <string>
#include <vector>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/detectability.h"

namespace tread_wear {
namespace diagnosis {

/// diagnosis.json's text: the verdict and its evidence, indented JSON (keys: docs/diagnosis.md).
std::string diagnosisJson(const DiagnosisResult& result, const DiagnosisData& data);
/// The human-readable report (Markdown). `plots` lists PNG file names to embed (may be empty).
std::string diagnosisMarkdown(const DiagnosisResult& result, const DiagnosisData& data, const std::string& source,
                              const std::vector<std::string>& plots);
/// The answer file's text (tread_wear_conceal), indented JSON; with a reference, also "detectability": lambda,
/// power, expected_right, terms_tried, verdicts (share per verdict) and parameters (value, std_error); NaN as null.
std::string answerJson(const ConcealAnswer& answer, const Detectability* reference);
/// Per-run residuals before/after and the covariates, as CSV text.
std::string residualsCsv(const DiagnosisResult& result, const DiagnosisData& data);

}  // namespace diagnosis
}  // namespace tread_wear
