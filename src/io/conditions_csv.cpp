#include "tread_wear/io/conditions_csv.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include "tread_wear/io/csv.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

const std::vector<std::string> kRequired = {"speed_mps", "slip_angle_rad", "slip_ratio", "path_radius_m", "load_n"};
const char* const kTemperature = "tread_temperature_c";

}  // namespace

ConditionsTable readConditions(std::istream& in, const std::string& source) {
  ConditionsTable table;
  std::vector<int> lines;
  std::string text;
  int line_no = 0;
  while (std::getline(in, text)) {
    ++line_no;
    const std::size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    std::vector<std::string> cells;
    std::string error;
    if (!csv::splitLine(text, &cells, &error))
      throw ConditionsError(source + ": line " + std::to_string(line_no) + ": " + error);
    if (table.header.empty()) {
      table.header = cells;
      std::set<std::string> seen;
      for (const std::string& name : cells) {
        bool known = name == kTemperature;
        for (const std::string& r : kRequired) known = known || name == r;
        if (!known)
          throw ConditionsError(source + ": line " + std::to_string(line_no) + ": unknown column '" + name +
                                "'; accepted: speed_mps, slip_angle_rad, slip_ratio, path_radius_m, load_n, "
                                "tread_temperature_c");
        if (!seen.insert(name).second)
          throw ConditionsError(source + ": line " + std::to_string(line_no) + ": column '" + name + "' appears twice");
      }
      for (const std::string& r : kRequired)
        if (csv::findColumn(cells, r) < 0)
          throw ConditionsError(source + ": line " + std::to_string(line_no) + ": missing column '" + r + "'");
      continue;
    }
    const int row = static_cast<int>(table.cells.size()) + 1;
    const std::string where = source + ": row " + std::to_string(row) + " (line " + std::to_string(line_no) + ")";
    if (cells.size() != table.header.size())
      throw ConditionsError(where + ": has " + std::to_string(cells.size()) + " cells, the header has " +
                            std::to_string(table.header.size()) + " (missing or extra column)");
    auto fail = [&](const std::string& column, const std::string& what) -> void {
      const std::string& cell = cells[csv::findColumn(table.header, column)];
      throw ConditionsError(where + ", column '" + column + "' = '" + cell + "': " + what);
    };
    auto number = [&](const std::string& column, bool empty_allowed, double fallback) {
      const int c = csv::findColumn(table.header, column);
      if (c < 0) return fallback;
      if (cells[c].empty()) {
        if (!empty_allowed) fail(column, "required, must not be empty");
        return fallback;
      }
      double value;
      if (!csv::parseFiniteDouble(cells[c], &value)) fail(column, "must be a finite number");
      return value;
    };
    OperatingPoint op;
    op.speed_mps = number("speed_mps", false, 0.0);
    if (op.speed_mps < 0.0) fail("speed_mps", "must be >= 0");
    op.slip_angle_rad = number("slip_angle_rad", false, 0.0);
    if (std::fabs(op.slip_angle_rad) >= 0.5 * units::kPi)
      fail("slip_angle_rad", "must satisfy |alpha| < pi/2 (90 deg; the unit is radians)");
    op.slip_ratio = number("slip_ratio", false, 0.0);
    if (op.slip_ratio <= -1.0) fail("slip_ratio", "must be > -1");
    const double radius_m = number("path_radius_m", true, 0.0);
    op.path_curvature_per_m = radius_m == 0.0 ? 0.0 : 1.0 / radius_m;
    op.load_n = number("load_n", false, 0.0);
    if (op.load_n <= 0.0) fail("load_n", "must be > 0");
    op.tread_temperature_c = number(kTemperature, true, op.tread_temperature_c);
    if (!op.validate(&error)) throw ConditionsError(where + ": " + error);
    table.cells.push_back(cells);
    table.points.push_back(op);
  }
  if (table.header.empty()) throw ConditionsError(source + ": no header row (and no conditions)");
  if (table.points.empty()) throw ConditionsError(source + ": no condition rows after the header");
  return table;
}

void writeEvaluations(std::ostream& out, const ConditionsTable& table, const std::vector<WearResult>& results) {
  if (results.size() != table.points.size()) throw std::invalid_argument("writeEvaluations: one result per row needed");
  for (const std::string& name : table.header) out << csv::quote(name) << ",";
  out << "fx_n,fy_n,mz_nm,wear_rate_kg_per_m,wear_rate_kg_per_s,stick_fraction,slide_fraction,exact_stick_fraction\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (const std::string& cell : table.cells[i]) out << csv::quote(cell) << ",";
    const WearResult& r = results[i];
    out << csv::formatDouble(r.fx_n) << "," << csv::formatDouble(r.fy_n) << "," << csv::formatDouble(r.mz_nm) << ","
        << csv::formatDouble(r.wear_rate_kg_per_m) << "," << csv::formatDouble(r.wear_rate_kg_per_s) << ","
        << csv::formatDouble(r.stick_fraction) << "," << csv::formatDouble(r.slide_fraction) << ","
        << csv::formatDouble(r.exact_stick_fraction) << "\n";
  }
}

}  // namespace tread_wear
