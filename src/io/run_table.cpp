#include "tread_wear/io/run_table.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "tread_wear/io/csv.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

const char* const kMarker = "# tread_wear run table v1";
const char* const kMarkerPrefix = "# tread_wear run table v";

/// Columns with a meaning of their own. The wear-derivation inputs (mass_loss_kg, distance_m, duration_s) are
/// not listed: RunRecord has no field for them, so they are also kept as covariates.
const std::set<std::string> kKnownColumns = {
    "speed_mps",   "slip_angle_rad", "slip_ratio", "path_radius_m", "load_n",         "tread_temperature_c",
    "load_mean_n", "load_std_n",     "condition_id", "cycle_id",    "run_order",      "side_force_n",
    "wear_rate_kg_per_m"};

/// Relative tolerance between a given wear rate and one derived from mass loss in the same row: the two are
/// the same number written twice, so they may differ only by the rounding of printing.
constexpr double kWearConsistencyRelTol = 1e-9;

std::string rstrip(const std::string& s) {
  const std::size_t end = s.find_last_not_of(" \t\r");
  return end == std::string::npos ? "" : s.substr(0, end + 1);
}

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void failLine(int line, const std::string& what) const {
    throw RunTableError(path_ + ":" + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void failCell(int line, int column, const std::string& what) const {
    const std::string& name = header_[column];
    throw RunTableError(path_ + ":" + std::to_string(line) + ":" + std::to_string(column + 1) + ": column '" + name +
                        "' = '" + cells_[column] + "': " + what);
  }

  RunTable read() {
    std::ifstream in(path_);
    if (!in) throw RunTableError(path_ + ": cannot open the file for reading");
    std::string text;
    int line_no = 0;
    bool have_header = false;
    std::vector<std::vector<std::string>> rows;
    std::vector<int> row_lines;
    while (std::getline(in, text)) {
      ++line_no;
      const std::string line = rstrip(text);
      if (line_no == 1) {
        if (line == kMarker) continue;
        if (line.rfind(kMarkerPrefix, 0) == 0)
          failLine(1, "unsupported run table version '" + line.substr(std::string(kMarkerPrefix).size()) +
                          "' (this build reads v1)");
        failLine(1, std::string("missing marker line: the first line must be '") + kMarker + "'");
      }
      if (line.empty() || line[0] == '#') continue;
      std::vector<std::string> cells;
      std::string error;
      if (!csv::splitLine(line, &cells, &error)) failLine(line_no, error);
      if (!have_header) {
        setHeader(cells, line_no);
        have_header = true;
        continue;
      }
      if (cells.size() != header_.size())
        failLine(line_no, "row has " + std::to_string(cells.size()) + " cells, the header has " +
                              std::to_string(header_.size()));
      rows.push_back(std::move(cells));
      row_lines.push_back(line_no);
    }
    if (line_no == 0) throw RunTableError(path_ + ": empty file (missing marker line '" + std::string(kMarker) + "')");
    if (!have_header) failLine(line_no, "no header row");
    if (rows.empty()) failLine(line_no, "the table has no runs");

    RunTable table;
    classifyCovariates(rows, &table);
    for (std::size_t r = 0; r < rows.size(); ++r) table.runs.push_back(parseRow(rows[r], row_lines[r]));
    return table;
  }

 private:
  void setHeader(const std::vector<std::string>& cells, int line_no) {
    header_ = cells;
    std::set<std::string> seen;
    for (std::size_t i = 0; i < header_.size(); ++i) {
      if (header_[i].empty()) failLine(line_no, "header column " + std::to_string(i + 1) + " has no name");
      if (!seen.insert(header_[i]).second) failLine(line_no, "header column '" + header_[i] + "' appears twice");
    }
    for (const char* required : {"speed_mps", "slip_angle_rad", "load_n"})
      if (csv::findColumn(header_, required) < 0)
        failLine(line_no, std::string("missing required column '") + required + "'");
  }

  void classifyCovariates(const std::vector<std::vector<std::string>>& rows, RunTable* table) {
    for (std::size_t c = 0; c < header_.size(); ++c) {
      if (kKnownColumns.count(header_[c])) continue;
      bool numeric = true;
      for (const auto& row : rows) {
        double value;
        numeric = numeric && (row[c].empty() || csv::parseFiniteDouble(row[c], &value));
      }
      if (numeric) {
        numeric_columns_.push_back(static_cast<int>(c));
        table->covariate_names.push_back(header_[c]);
      } else {
        text_columns_.push_back(static_cast<int>(c));
        table->text_covariate_names.push_back(header_[c]);
      }
    }
  }

  /// The cell of a column, or nullptr when the column is absent or the cell is empty.
  const std::string* cell(const char* name) const {
    const int c = csv::findColumn(header_, name);
    return (c < 0 || cells_[c].empty()) ? nullptr : &cells_[c];
  }

  double number(int line, const char* name, double fallback) const {
    const int c = csv::findColumn(header_, name);
    if (c < 0 || cells_[c].empty()) return fallback;
    double value;
    if (!csv::parseFiniteDouble(cells_[c], &value)) failCell(line, c, "must be a finite number");
    return value;
  }

  double required(int line, const char* name) const {
    const int c = csv::findColumn(header_, name);
    if (cells_[c].empty()) failCell(line, c, "required, must not be empty");
    return number(line, name, 0.0);
  }

  void check(bool ok, int line, const char* name, const char* constraint) const {
    if (!ok) failCell(line, csv::findColumn(header_, name), constraint);
  }

  RunRecord parseRow(const std::vector<std::string>& cells, int line) {
    cells_ = cells;
    RunRecord run;
    OperatingPoint& op = run.op;
    op.speed_mps = required(line, "speed_mps");
    check(op.speed_mps >= 0.0, line, "speed_mps", "must be >= 0");
    op.slip_angle_rad = required(line, "slip_angle_rad");
    check(std::fabs(op.slip_angle_rad) < 0.5 * units::kPi, line, "slip_angle_rad",
          "must satisfy |alpha| < pi/2 (radians, not degrees)");
    op.slip_ratio = number(line, "slip_ratio", 0.0);
    check(op.slip_ratio > -1.0, line, "slip_ratio", "must be > -1");
    const double radius_m = number(line, "path_radius_m", 0.0);
    op.path_curvature_per_m = radius_m == 0.0 ? 0.0 : 1.0 / radius_m;
    op.load_n = required(line, "load_n");
    check(op.load_n > 0.0, line, "load_n", "must be > 0");
    const double load_mean_n = number(line, "load_mean_n", op.load_n);
    check(load_mean_n > 0.0, line, "load_mean_n", "must be > 0");
    op.load_n = load_mean_n;
    op.tread_temperature_c = number(line, "tread_temperature_c", op.tread_temperature_c);
    run.load_std_n = number(line, "load_std_n", run.load_std_n);
    check(!(run.load_std_n < 0.0), line, "load_std_n", "must be >= 0");

    run.measured_side_force_n = number(line, "side_force_n", run.measured_side_force_n);
    run.measured_wear_rate_kg_per_m = measuredWear(line, op.speed_mps);

    if (const std::string* id = cell("condition_id")) {
      run.condition_id = *id;
    } else {
      std::ostringstream id_text;
      id_text.precision(6);
      id_text << "speed_mps=" << op.speed_mps << " slip_angle_rad=" << op.slip_angle_rad
              << " slip_ratio=" << op.slip_ratio << " path_radius_m=" << radius_m << " load_n=" << op.load_n;
      run.condition_id = id_text.str();
    }
    run.cycle_id = integer(line, "cycle_id");
    run.run_order = integer(line, "run_order");

    for (int c : numeric_columns_) {
      double value = std::numeric_limits<double>::quiet_NaN();
      if (!cells_[c].empty()) csv::parseFiniteDouble(cells_[c], &value);
      run.covariates.push_back(value);
    }
    for (int c : text_columns_) run.text_covariates.push_back(cells_[c]);
    return run;
  }

  int integer(int line, const char* name) const {
    const int c = csv::findColumn(header_, name);
    if (c < 0 || cells_[c].empty()) return -1;
    int value;
    if (!csv::parseInt(cells_[c], &value) || value < 0) failCell(line, c, "must be an integer >= 0");
    return value;
  }

  double measuredWear(int line, double speed_mps) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double rate = number(line, "wear_rate_kg_per_m", nan);
    check(!(rate < 0.0), line, "wear_rate_kg_per_m", "must be >= 0");
    const double mass_loss = number(line, "mass_loss_kg", nan);
    if (std::isnan(mass_loss)) return rate;
    check(mass_loss >= 0.0, line, "mass_loss_kg", "must be >= 0");
    double derived;
    const double distance = number(line, "distance_m", nan);
    if (!std::isnan(distance)) {
      check(distance > 0.0, line, "distance_m", "must be > 0");
      derived = mass_loss / distance;
    } else {
      const double duration = number(line, "duration_s", nan);
      if (std::isnan(duration))
        failCell(line, csv::findColumn(header_, "mass_loss_kg"),
                 "needs distance_m or duration_s in the same row to give a wear rate");
      check(duration > 0.0, line, "duration_s", "must be > 0");
      check(speed_mps > 0.0, line, "speed_mps", "must be > 0 to turn mass loss over a duration into a rate (Eq 2)");
      derived = mass_loss / (speed_mps * duration);  // Eq 2: W_r = dm / (v0 t)
    }
    if (!std::isnan(rate) && std::fabs(rate - derived) > kWearConsistencyRelTol * std::max(rate, derived))
      failCell(line, csv::findColumn(header_, "wear_rate_kg_per_m"),
               "disagrees with mass_loss_kg over the distance (" + csv::formatDouble(derived) + " kg/m)");
    return derived;
  }

  std::string path_;
  std::vector<std::string> header_;
  std::vector<std::string> cells_;
  std::vector<int> numeric_columns_;
  std::vector<int> text_columns_;
};

std::string cellOrEmpty(double value) { return std::isnan(value) ? "" : csv::formatDouble(value); }

}  // namespace

RunTable readRunTable(const std::string& path) { return Reader(path).read(); }

void writeRunTable(const RunTable& table, const std::string& path, const std::string& comment) {
  std::ofstream out(path);
  if (!out) throw RunTableError(path + ": cannot open the file for writing");
  out << kMarker << "\n";
  std::istringstream comment_lines(comment);
  for (std::string line; std::getline(comment_lines, line);) out << "# " << line << "\n";
  out << "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,tread_temperature_c,load_std_n,side_force_n,"
         "wear_rate_kg_per_m,condition_id,cycle_id,run_order";
  for (const std::string& name : table.covariate_names) out << "," << csv::quote(name);
  for (const std::string& name : table.text_covariate_names) out << "," << csv::quote(name);
  out << "\n";
  for (const RunRecord& run : table.runs) {
    const OperatingPoint& op = run.op;
    const double radius_m = op.path_curvature_per_m == 0.0 ? 0.0 : 1.0 / op.path_curvature_per_m;
    out << csv::formatDouble(op.speed_mps) << "," << csv::formatDouble(op.slip_angle_rad) << ","
        << csv::formatDouble(op.slip_ratio) << "," << csv::formatDouble(radius_m) << ","
        << csv::formatDouble(op.load_n) << "," << cellOrEmpty(op.tread_temperature_c) << ","
        << cellOrEmpty(run.load_std_n) << "," << cellOrEmpty(run.measured_side_force_n) << ","
        << cellOrEmpty(run.measured_wear_rate_kg_per_m) << "," << csv::quote(run.condition_id) << ","
        << (run.cycle_id < 0 ? "" : std::to_string(run.cycle_id)) << ","
        << (run.run_order < 0 ? "" : std::to_string(run.run_order));
    for (double value : run.covariates) out << "," << cellOrEmpty(value);
    for (const std::string& text : run.text_covariates) out << "," << csv::quote(text);
    out << "\n";
  }
  out.flush();
  if (!out) throw RunTableError(path + ": writing failed");
}

RunRecord driveSegmentRecord(const DriveSegment& segment, double repetitions) {
  RunRecord r;
  r.op = segment.mean;
  r.load_std_n = segment.load_std_n;
  r.drive_points = segment.points;
  for (WeightedOperatingPoint& p : r.drive_points) {
    p.time_s *= repetitions;
    p.distance_m *= repetitions;
  }
  r.drive_time_s = repetitions * segment.integrated_s;
  r.drive_distance_m = repetitions * segment.distance_m;
  return r;
}

}  // namespace tread_wear
