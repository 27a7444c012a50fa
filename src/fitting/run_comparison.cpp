#include "tread_wear/fitting/run_comparison.h"

#include <cmath>
#include <stdexcept>

#include "tread_wear/fitting/metrics.h"

namespace tread_wear {

PointModel wearModelPoint(const WearModel& model) {
  return [&model](const OperatingPoint& op, WearResult* result) {
    if (model.evaluate(op, result) == EvalStatus::kInvalidInput) {
      std::string error;
      op.validate(&error);
      throw std::invalid_argument("invalid operating point: " + error);
    }
  };
}

RunComparison compareRuns(const RunTable& table, const PointModel& model, const LoadBinningOptions& binning) {
  RunComparison comparison;
  std::vector<double> measured_fy, predicted_fy, measured_wr, predicted_wr;
  for (const RunRecord& run : table.runs) {
    RunPrediction prediction;
    const std::vector<LoadBin> bins = normalLoadBins(run.op.load_n, run.load_std_n, binning);
    prediction.load_bins = static_cast<int>(bins.size());
    OperatingPoint op = run.op;
    WearResult result;
    for (const LoadBin& bin : bins) {
      op.load_n = bin.centre_n;
      model(op, &result);
      prediction.side_force_n += bin.weight * result.fy_n;
      prediction.wear_rate_kg_per_m += bin.weight * result.wear_rate_kg_per_m;  // Eq 23
    }
    if (!std::isnan(run.measured_side_force_n)) {
      measured_fy.push_back(run.measured_side_force_n);
      predicted_fy.push_back(prediction.side_force_n);
      prediction.side_force_error_ratio = errorRatios({run.measured_side_force_n}, {prediction.side_force_n})[0];
    }
    if (!std::isnan(run.measured_wear_rate_kg_per_m)) {
      measured_wr.push_back(run.measured_wear_rate_kg_per_m);
      predicted_wr.push_back(prediction.wear_rate_kg_per_m);
      prediction.wear_error_ratio = errorRatios({run.measured_wear_rate_kg_per_m}, {prediction.wear_rate_kg_per_m})[0];
    }
    comparison.runs.push_back(prediction);
  }
  comparison.n_side_force = static_cast<int>(measured_fy.size());
  comparison.n_wear = static_cast<int>(measured_wr.size());
  if (!measured_fy.empty()) comparison.rmser_side_force = rmser(measured_fy, predicted_fy);
  if (!measured_wr.empty()) comparison.rmser_wear = rmser(measured_wr, predicted_wr);
  return comparison;
}

}  // namespace tread_wear
