#pragma once
/// @file conditions_csv.h
/// CSV of operating conditions for the evaluator (tread_wear_eval) and its CSV output.
/// Input: a header row, then one row per condition (CSV rules as csv.h; '#' lines and blank lines skipped).
///   required  speed_mps [m/s] (>= 0), slip_angle_rad [rad] (|alpha| < pi/2), slip_ratio [-] (> -1),
///             path_radius_m [m] (ISO sign, left turn positive; 0 or empty = straight, curvature = 1/R),
///             load_n [N] (> 0)
///   optional  tread_temperature_c [degC] (empty = unknown)
/// Any other column is an error (a misspelt or wrong-unit column must not be silently ignored).
/// Output: the input columns as given, then fx_n, fy_n, mz_nm, wear_rate_kg_per_m, wear_rate_kg_per_s,
/// stick_fraction, slide_fraction, exact_stick_fraction in round-trip double precision.
/// Signs: ISO 8855 tire axes, forces the road applies to the tire (operating_point.h).

#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/operating_point.h"

namespace tread_wear {

struct ConditionsTable {
  std::vector<std::string> header;               ///< input columns, as given
  std::vector<std::vector<std::string>> cells;   ///< input cells per row, as given
  std::vector<OperatingPoint> points;            ///< parsed conditions, one per row
};

/// Error naming the source, the 1-based data row, its line, the column and the cell.
class ConditionsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads and validates all rows. An input without rows is an error. @throw ConditionsError
ConditionsTable readConditions(std::istream& in, const std::string& source_name);
/// Writes the input columns and the results (results.size() == table.points.size()).
void writeEvaluations(std::ostream& out, const ConditionsTable& table, const std::vector<WearResult>& results);

}  // namespace tread_wear
