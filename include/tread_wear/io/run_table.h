#pragma once
/// @file run_table.h
/// Run tables: one row per test run (rig or road), the input of calibration and mismatch diagnosis.
/// Versioned CSV, documented in docs/run_table.md. The first line is the marker
///   # tread_wear run table v1
/// then optional further '#' comment lines, then a header row and one row per run.
///
/// Columns (SI, as the evaluator's):
///   required  speed_mps, slip_angle_rad, load_n
///   optional  slip_ratio (default 0), path_radius_m (ISO sign; 0 or empty = straight),
///             tread_temperature_c, load_mean_n (overrides load_n for the model when given),
///             load_std_n (Eq 23 binning), condition_id (text), cycle_id (integer), run_order (integer)
///   measured  side_force_n;
///             wear_rate_kg_per_m, or mass_loss_kg with distance_m, or mass_loss_kg with duration_s
///             (distance = speed * duration, Eq 2); any measured cell may be empty (not measured)
///   any other column is a covariate: kept by name, numeric when every non-empty cell parses, else text.

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "tread_wear/estimation/drive_segments.h"
#include "tread_wear/model/operating_point.h"

namespace tread_wear {

struct RunRecord {
  OperatingPoint op;  ///< conditions (load_n = load_mean_n when given)
  double measured_side_force_n = std::numeric_limits<double>::quiet_NaN();        ///< [N]; NaN = not measured
  double measured_wear_rate_kg_per_m = std::numeric_limits<double>::quiet_NaN();  ///< [kg/m]; NaN = not measured
  double load_std_n = std::numeric_limits<double>::quiet_NaN();  ///< load standard deviation [N]; NaN = unknown
  std::string condition_id;  ///< label of the condition (repeats share it); defaults to the row's conditions
  int cycle_id = -1;         ///< test cycle; -1 = unknown
  int run_order = -1;        ///< order within the campaign; -1 = unknown
  std::vector<double> covariates;            ///< numeric extra columns, aligned with RunTable::covariate_names
  std::vector<std::string> text_covariates;  ///< text extra columns, aligned with RunTable::text_covariate_names
  /// A drive segment (not in the CSV format): the operating points integrated over it with their weights
  /// (estimation/drive_segments.h); empty for a steady run, which the model evaluates at `op`.
  std::vector<WeightedOperatingPoint> drive_points;
  double drive_time_s = 0.0;      ///< integrated time of the segment [s]
  double drive_distance_m = 0.0;  ///< integrated distance of the segment, zero-load steps included [m]
};

struct RunTable {
  int version = 1;
  std::vector<std::string> covariate_names;       ///< numeric extra columns
  std::vector<std::string> text_covariate_names;  ///< text extra columns
  std::vector<RunRecord> runs;
};

/// Error naming the file, the 1-based line, the column and what is wrong.
class RunTableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads and validates a run table; an empty table is an error. @throw RunTableError
RunTable readRunTable(const std::string& path);
/// The record of a drive segment (estimation/drive_segments.h) driven `repetitions` times over: op = its means,
/// its load std, its points and its integrated time and distance, every weight times `repetitions` [-], > 0.
/// Measurements, labels and covariates are the caller's.
RunRecord driveSegmentRecord(const DriveSegment& segment, double repetitions = 1.0);
/// Writes a run table in format v1 (measured wear as wear_rate_kg_per_m).
void writeRunTable(const RunTable& table, const std::string& path, const std::string& comment = "");

}  // namespace tread_wear
