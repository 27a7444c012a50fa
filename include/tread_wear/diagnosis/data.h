#pragma once
/// @file data.h
/// The recordings the mismatch diagnosis works on: the runs of a run table (run_table.h) with the covariates
/// derived from them. A run is one test run (rig) or one wheel's segment of a drive between two measurement
/// checkpoints (bag), which carries the operating points it integrates (drive_points).
///
/// Derived per run (the sequence covariates the candidate terms need):
///   lateral sliding distance  L_s = distance |sin(alpha)|   (paper Eq 1; distance = distance_m, or
///                              speed * duration_s; unknown when neither is recorded)
///   cumulative sliding        sliding distance on the current surface at the middle of the run: sum of L_s of
///                              the earlier runs of the same cycle (ordered by run_order, else row order) plus
///                              half its own. A cycle is the span between surface renewals (paper Section 2.2:
///                              the disc is sandblasted after each cycle). Runs without cycle_id form one cycle.
/// Covariates offered to the locating tests: the operating region (load, |slip angle|, speed, tread
/// temperature, load std), the sequence (run order, cumulative sliding distance, cycle) and every other
/// recorded column of the run table (numeric: trend tests; text: group tests). Columns that restate a
/// measurement (mass_loss_kg) are left out.

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "tread_wear/io/run_table.h"

namespace tread_wear {
namespace diagnosis {

/// The two measured outputs the diagnosis compares.
enum class Output { kSideForce = 0, kWear = 1 };
constexpr int kNumOutputs = 2;
/// "side_force" or "wear".
const char* outputName(Output output);

/// Error in the recordings (too few runs, nothing measured, ...): a clear message for the user.
class DiagnosisError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DiagnosisRun {
  OperatingPoint op;  ///< conditions; op.tread_temperature_c is NaN (temperature enters through the terms)
  double load_std_n = std::numeric_limits<double>::quiet_NaN();           ///< recorded load std [N]
  double tread_temperature_c = std::numeric_limits<double>::quiet_NaN();  ///< recorded tread temperature [degC]
  double sliding_distance_m = std::numeric_limits<double>::quiet_NaN();   ///< L_s of this run (Eq 1) [m]
  double cumulative_sliding_m = std::numeric_limits<double>::quiet_NaN(); ///< at the middle of the run [m]
  /// Fy [N], W_r [kg/m]; NaN = not measured
  double measured[kNumOutputs] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  std::string condition;  ///< condition label (repeats share it)
  int cycle = -1;         ///< surface cycle (-1 = unknown)
  int run_order = -1;     ///< order in the campaign (-1 = unknown)
  /// A drive segment's integrated operating points (RunRecord::drive_points); empty for a steady run. The model
  /// then predicts W_r = sum W_r(op_k) d_k / drive_distance_m and Fy = sum Fy(op_k) t_k / drive_time_s.
  std::vector<WeightedOperatingPoint> drive_points;
  double drive_time_s = 0.0;      ///< [s]
  double drive_distance_m = 0.0;  ///< [m]
  bool isDrive() const { return !drive_points.empty(); }
};

/// A covariate the locating tests look at.
struct Covariate {
  std::string name;      ///< e.g. "load_n", "cumulative_sliding_m", "humidity_percent"
  std::string kind;      ///< "operating region", "sequence" or "recorded"
  bool categorical = false;
  std::vector<double> values;  ///< numeric value per run (NaN = missing); categorical: group index per run
  std::vector<std::string> levels;  ///< categorical: label of each group index
};

struct DriveCells;

struct DiagnosisData {
  std::vector<DiagnosisRun> runs;
  /// The drive segments' cells and their base evaluations (extensions.h), built by the first model that needs
  /// them and shared by every model of these data; null until then or without drive segments.
  mutable std::shared_ptr<DriveCells> drive_cells;
  std::vector<Covariate> covariates;
  bool has_temperature = false;        ///< every run has a tread temperature
  bool has_sequence = false;           ///< every run has a cumulative sliding distance
  bool has_load_std = false;           ///< some run has a load std > 0
  bool has_turn_slip = false;          ///< some run has a path curvature (orientation matters)
  int measured_count[kNumOutputs] = {0, 0};
  std::vector<std::string> cv_groups;  ///< cross-validation group of each run
  /// "leave one cycle out", "leave one period out" (drive segments of all wheels between the same two checkpoints,
  /// by run order), "leave one condition out" or "leave one run out"
  std::string cv_scheme;
  /// Per run: 1 where the run calibrates its held-out group's wear scale (calibrateHeldOutGroupsOn); empty = none.
  std::vector<char> cv_calibration_run;
  /// Values left out while screening the recordings, "run i (condition 'c'): why" (recording_checks.h)
  std::vector<std::string> warnings;
};

/// Cross-validation by whole groups of a categorical covariate (e.g. the text covariates `brand` or `test` of a
/// drive bag): every fold holds out all runs of one of its levels, cv_scheme "leave one <covariate> out". A term
/// with one offset per group then cannot predict a group it has not seen. @throw DiagnosisError when `covariate` is
/// not a categorical covariate of the data (the error lists those that are) or it has fewer than 2 levels.
void holdOutGroups(DiagnosisData* data, const std::string& covariate);

/// A held-out group is predicted as a new tyre would be: with its own wear scale, one factor fitted on its runs
/// whose categorical `covariate` is `level` (e.g. test Run-in: one abrasivity per brand from its own run-in, as
/// the LEON-T comparison calibrates), every other parameter from the training groups. Those runs are then
/// calibration, not prediction: they leave the held-out error. @throw DiagnosisError when `covariate` is not a
/// categorical covariate, `level` is not one of its levels, or a cross-validation group has no run at `level` or
/// nothing else (the error names the group).
void calibrateHeldOutGroupsOn(DiagnosisData* data, const std::string& covariate, const std::string& level);

/// Builds the diagnosis records from a run table. @throw DiagnosisError when fewer than 4 runs have a
/// measurement or a measured value is not positive (the relative errors of Eq 24 need a positive value).
DiagnosisData buildDiagnosisData(const RunTable& table);

}  // namespace diagnosis
}  // namespace tread_wear
