#pragma once
/// @file calibration_report.h
/// The calibration result (fitting/calibration.h) as JSON, the file tread_wear_calibrate writes (docs/calibration.md).

#include <string>
#include <vector>

#include "tread_wear/fitting/calibration.h"

namespace tread_wear {

/// The file's text, indented JSON: rmser_side_force, rmser_wear, cv_rmser_side_force, cv_rmser_wear, rmse_*,
/// initial_*, parameters {name: value, std_error, lower, upper, at_bound, unit, paper_value, paper_unit},
/// correlations, condition_number, residuals (per run), termination, usable, folds, data_warnings (the run
/// table's, as the tool printed them); NaN as null.
std::string calibrationJson(const CalibrationResult& result, const std::vector<std::string>& data_warnings);

}  // namespace tread_wear
