#include "tread_wear/report/calibration_report.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "tread_wear/model/wear_model.h"

namespace tread_wear {

std::string calibrationJson(const CalibrationResult& result, const std::vector<std::string>& data_warnings) {
  using nlohmann::json;
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  const LeastSquaresSummary& s = result.summary;
  json j;
  j["target"] = targetName(result.target);
  j["orientation"] = orientationName(result.options.orientation);
  j["grid"] = {{"n_x_steps", result.options.grid.n_x_steps}, {"n_strips", result.options.grid.n_strips},
               {"turn_slip_iterations", result.options.turn_slip_iterations}};
  j["prior_weight"] = result.options.prior_weight;
  j["rmser_side_force"] = num(result.fitted.rmser_side_force);
  j["rmser_wear"] = num(result.fitted.rmser_wear);
  j["rmse_side_force_n"] = num(result.fitted.rmse_side_force_n);
  j["rmse_wear_kg_per_m"] = num(result.fitted.rmse_wear_kg_per_m);
  j["cv_rmser_side_force"] = num(result.cross_validated.rmser_side_force);
  j["cv_rmser_wear"] = num(result.cross_validated.rmser_wear);
  j["cv_rmse_side_force_n"] = num(result.cross_validated.rmse_side_force_n);
  j["cv_rmse_wear_kg_per_m"] = num(result.cross_validated.rmse_wear_kg_per_m);
  j["initial_rmser_side_force"] = num(result.initial.rmser_side_force);
  j["initial_rmser_wear"] = num(result.initial.rmser_wear);
  j["termination"] = terminationName(s.termination);
  j["message"] = s.message;
  j["usable"] = s.usable;
  j["iterations"] = s.iterations;
  j["initial_cost"] = num(s.initial_cost);
  j["final_cost"] = num(s.final_cost);
  j["condition_number"] = num(s.condition_number);
  j["degrees_of_freedom"] = s.degrees_of_freedom;
  j["residual_variance"] = num(s.residual_variance);
  j["standard_errors"] = s.robust_covariance ? "hc3" : "classic";
  json params = json::array();
  for (const ParameterEstimate& p : s.parameters) {
    const ParameterInfo* info = findParameter(p.name);
    params.push_back({{"name", p.name},
                      {"value", num(p.value)},
                      {"std_error", num(p.std_error)},
                      {"bounds", {num(p.lower), num(p.upper)}},
                      {"at_bound", p.atBound()},
                      {"at_lower", p.at_lower},
                      {"at_upper", p.at_upper},
                      {"unit", info->unit},
                      {"paper_value", num(p.value * info->to_paper)},
                      {"paper_std_error", num(p.std_error * info->to_paper)},
                      {"paper_unit", info->paper_unit}});
  }
  j["parameters"] = params;
  json corr = json::array();
  for (int a = 0; a < s.correlation.rows(); ++a) {
    json row = json::array();
    for (int b = 0; b < s.correlation.cols(); ++b) row.push_back(num(s.correlation(a, b)));
    corr.push_back(row);
  }
  j["correlations"] = {{"names", result.options.fit}, {"matrix", corr}};
  json res = json::array();
  for (const CalibratedRun& r : result.runs) {
    res.push_back({{"condition_id", r.condition_id},
                   {"measured_side_force_n", num(r.measured_side_force_n)},
                   {"side_force_n", num(r.side_force_n)},
                   {"error_ratio_side_force", num(r.side_force_n / r.measured_side_force_n - 1.0)},
                   {"cv_side_force_n", num(r.cv_side_force_n)},
                   {"cv_error_ratio_side_force", num(r.cv_side_force_n / r.measured_side_force_n - 1.0)},
                   {"measured_wear_rate_kg_per_m", num(r.measured_wear_rate_kg_per_m)},
                   {"wear_rate_kg_per_m", num(r.wear_rate_kg_per_m)},
                   {"error_ratio_wear", num(r.wear_rate_kg_per_m / r.measured_wear_rate_kg_per_m - 1.0)},
                   {"cv_wear_rate_kg_per_m", num(r.cv_wear_rate_kg_per_m)},
                   {"cv_error_ratio_wear", num(r.cv_wear_rate_kg_per_m / r.measured_wear_rate_kg_per_m - 1.0)},
                   {"initial_side_force_n", num(r.initial_side_force_n)},
                   {"initial_wear_rate_kg_per_m", num(r.initial_wear_rate_kg_per_m)}});
  }
  j["residuals"] = res;
  json folds = json::array();
  for (const CrossValidationFold& f : result.folds) {
    json values = json::object();
    for (size_t k = 0; k < f.values.size(); ++k) values[result.options.fit[k]] = num(f.values[k]);
    folds.push_back({{"held_out", f.group}, {"termination", terminationName(f.termination)},
                     {"usable", f.usable}, {"values", values}});
  }
  j["folds"] = folds;
  j["data_warnings"] = data_warnings;
  return j.dump(2) + "\n";
}

}  // namespace tread_wear
