#pragma once
/// @file calibration.h
/// Calibration of the brush wear model (brush_wear_model.h) to a run table (run_table.h) with the bounded
/// least-squares engine (least_squares.h), plus leave-one-condition-out cross-validation.
///
/// Parameters are chosen by NAME from a registry that covers every physical parameter of TireParams
/// (footprint Eqs 6-8, friction Eqs 10-11, tread Eqs 12-13, wear law Eqs 19 and 25), each with its SI unit,
/// physical bounds and whether it is optimised in log space (strictly positive quantities).
///
/// Residuals are error ratios (Eq 24): r = predicted/measured - 1 per fitted output, each multiplied by
/// its weight, so the fit minimises the (weighted) RMSER the paper reports. Optional Gaussian priors pull
/// each fitted parameter toward its value in the starting parameter file: one extra residual
/// prior_weight * (u - u_file) per parameter, with u = ln(value) for log-scale parameters and
/// u = value/|value_file| otherwise. So with prior_weight W, a parameter 10% away from the file costs as
/// much as one run with an error ratio of 0.1 W; W = 0 disables priors.
///
/// Model evaluation per run: compareRuns (run_comparison.h): the run's conditions; when the run table gives
/// load_std_n, Fy and W_r are Eq 23 load-binned averages over a normal load distribution; otherwise both at the
/// given (mean) load.
/// Cross-validation groups are the runs' condition_id, so repeats of one condition are held out together.
/// Limits: a local optimum from the parameter file's values; standard errors are linearised.

#include <string>
#include <vector>

#include "tread_wear/fitting/least_squares.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/load_binning.h"
#include "tread_wear/model/tire_params.h"

namespace tread_wear {

/// A calibratable parameter of TireParams.
struct ParameterInfo {
  const char* name;        ///< registry name, e.g. "k_y0"
  const char* unit;        ///< SI unit of the value
  const char* paper_unit;  ///< unit the paper prints (Table 4)
  double to_paper;         ///< paper value = SI value * to_paper
  double lower, upper;     ///< physical bounds [SI]
  bool log_scale;          ///< strictly positive: fit ln(value)
  double* (*field)(TireParams*);  ///< the member this entry names
};

/// Every calibratable parameter, in the order footprint, friction, tread, wear.
const std::vector<ParameterInfo>& parameterRegistry();
/// Registry entry by name; nullptr when unknown.
const ParameterInfo* findParameter(const std::string& name);
/// Value [SI] of a named parameter. @throw std::invalid_argument for an unknown name
double getParameter(const TireParams& params, const std::string& name);
/// Sets a named parameter [SI]. @throw std::invalid_argument for an unknown name
void setParameter(TireParams* params, const std::string& name, double value);
/// Splits "a,b,c" into names and checks each against the registry. @throw std::invalid_argument
std::vector<std::string> parseParameterList(const std::string& comma_separated);
/// True for w1..w4, T0, sigma_T (they do not change the forces).
bool isWearLawParameter(const std::string& name);

/// Which measured outputs the fit uses.
enum class CalibrationTarget { kAuto, kSideForce, kWear, kBoth };
const char* targetName(CalibrationTarget target);
bool parseTarget(const std::string& name, CalibrationTarget* target);

struct CalibrationOptions {
  std::vector<std::string> fit = {"w1", "w2", "w3", "w4"};  ///< parameters to fit, by registry name
  CalibrationTarget target = CalibrationTarget::kAuto;     ///< kAuto: wear if only wear-law parameters, else both
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  double side_force_weight = 1.0;  ///< weight on Fy error ratios (kBoth) [-], >= 0
  double wear_weight = 1.0;        ///< weight on W_r error ratios (kBoth) [-], >= 0
  double prior_weight = 0.0;       ///< Gaussian prior strength toward the file's values [-], >= 0; 0 = none
  /// Grid of the brush model during the fit. 400 x 24 with 2 turn-slip passes is within 0.07% (Fy) and
  /// 0.15% (W_r) of the reference preset on the Table 3 conditions at 1/16 of its cost.
  GridSpec grid{400, 24, 0.8};
  int turn_slip_iterations = 2;
  bool cross_validate = true;      ///< leave-one-condition-out for the fit
  LoadBinningOptions binning;      ///< Eq 23 (used when the run table gives load_std_n)
  LeastSquaresOptions solver = defaultSolverOptions();

  bool validate(std::string* error) const;
  /// Finite-difference step 1e-3 in ln(value) (or value/|value|): larger than the grid's switching noise.
  static LeastSquaresOptions defaultSolverOptions();
};

/// Measured and predicted outputs of one run (NaN where not measured or not computed).
struct CalibratedRun {
  std::string condition_id;
  double measured_side_force_n, measured_wear_rate_kg_per_m;
  double side_force_n, wear_rate_kg_per_m;        ///< calibrated parameters, in sample
  double cv_side_force_n, cv_wear_rate_kg_per_m;  ///< parameters fitted without this run's condition
  double initial_side_force_n, initial_wear_rate_kg_per_m;  ///< parameter file's values
};

/// Goodness of fit over the runs that measured an output (fractions; NaN when nothing to compare).
struct FitMetrics {
  double rmser_side_force, rmser_wear;  ///< Eq 24
  double rmse_side_force_n, rmse_wear_kg_per_m;  ///< Eq 21
};

struct CalibrationResult {
  TireParams params;  ///< the parameter file's values with the fitted ones replaced
  CalibrationOptions options;
  CalibrationTarget target;  ///< resolved target
  LeastSquaresSummary summary;
  std::vector<CalibratedRun> runs;
  FitMetrics initial, fitted, cross_validated;
  std::vector<CrossValidationFold> folds;
};

/// Fits options.fit to the run table starting from `initial`. @throw std::invalid_argument for invalid
/// options, unknown names, or a table without the measurements the target needs.
CalibrationResult calibrate(const TireParams& initial, const RunTable& runs, const CalibrationOptions& options);

/// Predicted (Fy, W_r) of each run with the given parameters on the calibration grid (compareRuns).
/// @throw std::invalid_argument when the parameters are invalid.
std::vector<std::pair<double, double>> predictRuns(const TireParams& params, const RunTable& runs,
                                                   const CalibrationOptions& options);

}  // namespace tread_wear
