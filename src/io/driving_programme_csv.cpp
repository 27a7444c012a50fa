#include "tread_wear/io/driving_programme_csv.h"

#include <fstream>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

#include "tread_wear/io/csv.h"

namespace tread_wear {

namespace {

/// A CSV file read whole: its header and rows, each with its line number for messages.
class Table {
 public:
  explicit Table(std::string path) : path_(std::move(path)) {
    std::ifstream in(path_);
    if (!in) throw std::runtime_error(path_ + ": cannot open");
    std::string line, error;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::vector<std::string> cells;
      if (!csv::splitLine(line, &cells, &error)) fail(number, error);
      if (header_.empty())
        header_ = std::move(cells);
      else
        rows_.push_back({number, std::move(cells)});
    }
    if (header_.empty()) throw std::runtime_error(path_ + ": empty file");
  }

  std::size_t rows() const { return rows_.size(); }
  std::string text(std::size_t row, const std::string& column) const { return cell(row, column); }
  double number(std::size_t row, const std::string& column) const {
    double value = 0.0;
    if (!csv::parseFiniteDouble(cell(row, column), &value))
      fail(rows_[row].first, "'" + column + "' is not a finite number: '" + cell(row, column) + "'");
    return value;
  }
  int integer(std::size_t row, const std::string& column) const {
    int value = 0;
    if (!csv::parseInt(cell(row, column), &value))
      fail(rows_[row].first, "'" + column + "' is not an integer: '" + cell(row, column) + "'");
    return value;
  }
  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw std::runtime_error(path_ + ":" + std::to_string(line) + ": " + problem);
  }
  int line(std::size_t row) const { return rows_[row].first; }

 private:
  std::string cell(std::size_t row, const std::string& column) const {
    const int index = csv::findColumn(header_, column);
    if (index < 0) throw std::runtime_error(path_ + ": no column '" + column + "'");
    const auto& cells = rows_[row].second;
    if (static_cast<std::size_t>(index) >= cells.size()) fail(rows_[row].first, "no cell for '" + column + "'");
    return cells[static_cast<std::size_t>(index)];
  }
  std::string path_;
  std::vector<std::string> header_;
  std::vector<std::pair<int, std::vector<std::string>>> rows_;
};

ProgrammeManoeuvreKind manoeuvreKind(const Table& table, std::size_t row) {
  const std::string code = table.text(row, "Maneuver code");
  if (code == "Acceleration") return ProgrammeManoeuvreKind::kAcceleration;
  if (code == "Deceleration") return ProgrammeManoeuvreKind::kDeceleration;
  if (code == "Constant") return ProgrammeManoeuvreKind::kConstant;
  table.fail(table.line(row), "Maneuver code must be Acceleration, Deceleration or Constant, not '" + code + "'");
}

}  // namespace

DrivingProgramme readDrivingProgramme(const std::string& dir, const std::string& turns_path) {
  const Table turns(turns_path);
  std::map<std::pair<std::string, std::string>, int> turn_of;
  for (std::size_t r = 0; r < turns.rows(); ++r) {
    const std::string turn = turns.text(r, "turn");
    if (turn != "left" && turn != "right") turns.fail(turns.line(r), "turn must be left or right, not '" + turn + "'");
    turn_of[{turns.text(r, "Track"), turns.text(r, "Sector number")}] = turn == "left" ? 1 : -1;
  }

  DrivingProgramme programme;
  const Table sectors(dir + "/sectors.csv");
  for (std::size_t r = 0; r < sectors.rows(); ++r) {
    const std::string track = sectors.text(r, "Track");
    if (programme.track(track) == nullptr) programme.tracks.push_back({track, {}});
    ProgrammeSector s;
    s.id = sectors.text(r, "Sector number");
    s.name = sectors.text(r, "Sector name");
    s.length_m = sectors.number(r, "Distance (m)");
    s.grade_percent = sectors.number(r, "Longitudinal slope (%)");
    s.crossfall_percent = sectors.number(r, "Latitudinal slope (%)");
    s.radius_m = sectors.number(r, "Corner radius (m)");
    s.angle_deg = sectors.number(r, "Corner angle (degrees)");
    if (s.radius_m > 0.0) {
      const auto turn = turn_of.find({track, s.id});
      if (turn == turn_of.end())
        sectors.fail(sectors.line(r), "corner " + s.id + " of '" + track + "' has no turn in " + turns_path);
      s.turn = turn->second;
    }
    for (Track& t : programme.tracks)
      if (t.name == track) t.sectors.push_back(s);
  }

  const Table sections(dir + "/test_sections.csv");
  for (std::size_t r = 0; r < sections.rows(); ++r) {
    ProgrammeSection s;
    s.id = sections.text(r, "Test section");
    s.name = sections.text(r, "Section name");
    s.test = sections.text(r, "AbrasionTest");
    s.track = sections.text(r, "Track");
    s.laps = sections.integer(r, "Number of laps");
    s.declared_distance_km = sections.number(r, "Total distance (km)");
    programme.sections.push_back(std::move(s));
  }

  const Table manoeuvres(dir + "/maneuvers.csv");
  for (std::size_t r = 0; r < manoeuvres.rows(); ++r) {
    const std::string id = manoeuvres.text(r, "Test section");
    ProgrammeSection* section = nullptr;
    for (ProgrammeSection& s : programme.sections)
      if (s.id == id && s.track == manoeuvres.text(r, "Track")) section = &s;
    if (section == nullptr)
      manoeuvres.fail(manoeuvres.line(r), "test section '" + id + "' on that track is not in test_sections.csv");
    ProgrammeManoeuvre m;
    m.sector_id = manoeuvres.text(r, "Sector number");
    m.kind = manoeuvreKind(manoeuvres, r);
    m.repeats = manoeuvres.integer(r, "Maneuver repeats");
    m.start_speed_mps = manoeuvres.number(r, "Start speed (m/s)");
    m.end_speed_mps = manoeuvres.number(r, "End speed (m/s)");
    m.accel_mps2 = manoeuvres.number(r, "Acceleration constant (m.s^-2)");
    m.decel_mps2 = manoeuvres.number(r, "Deceleration constant (m.s^-2)");
    section->manoeuvres.push_back(m);
  }

  std::string error;
  if (!programme.validate(&error)) throw std::runtime_error(dir + ": " + error);
  return programme;
}

}  // namespace tread_wear
