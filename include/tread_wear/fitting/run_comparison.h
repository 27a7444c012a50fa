#pragma once
/// @file run_comparison.h
/// Model against measured runs (a run table): predicted side force and wear rate per run, error ratios and
/// RMSER (Eq 24). When a run has a load standard deviation, the prediction is the Eq 23 weighted average over
/// load bins of a normal distribution (load_binning.h), for Fy as well as W_r.

#include <functional>
#include <limits>
#include <vector>

#include "tread_wear/io/run_table.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/load_binning.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {

/// Evaluates one valid operating point (speed may be 0 if the model has a low-speed convention).
using PointModel = std::function<void(const OperatingPoint& op, WearResult* result)>;

/// A PointModel over a WearModel at its active preset. The WearModel must outlive it.
/// @throw std::invalid_argument (when called) for a point that fails OperatingPoint::validate().
PointModel wearModelPoint(const WearModel& model);

struct RunPrediction {
  double side_force_n = 0.0;        ///< predicted Fy [N]
  double wear_rate_kg_per_m = 0.0;  ///< predicted W_r [kg/m]
  double side_force_error_ratio = std::numeric_limits<double>::quiet_NaN();  ///< Eq 24 y_i [-]; NaN = not measured
  double wear_error_ratio = std::numeric_limits<double>::quiet_NaN();        ///< Eq 24 y_i [-]; NaN = not measured
  int load_bins = 1;                ///< number of Eq 23 load bins evaluated
};

struct RunComparison {
  std::vector<RunPrediction> runs;  ///< aligned with RunTable::runs
  double rmser_side_force = std::numeric_limits<double>::quiet_NaN();  ///< over runs with measured Fy [-]
  int n_side_force = 0;
  double rmser_wear = std::numeric_limits<double>::quiet_NaN();  ///< over runs with measured W_r [-]
  int n_wear = 0;
};

/// Predicts every run and computes the error ratios and RMSERs. @throw std::invalid_argument from the model
/// or when a measured value is 0 (Eq 24 undefined).
RunComparison compareRuns(const RunTable& table, const PointModel& model, const LoadBinningOptions& binning = {});

}  // namespace tread_wear
