#include "tread_wear/io/speed_profile_csv.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "tread_wear/io/csv.h"

namespace tread_wear {

namespace {

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r.");
  return s.substr(begin, end - begin + 1);
}

}  // namespace

bool parsePhaseList(const std::string& text, std::vector<ProfilePhase>* phases, std::string* error) {
  phases->clear();
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    const auto space = item.find_last_of(' ');
    const auto dash = item.find('-', space == std::string::npos ? 0 : space);
    if (space == std::string::npos || dash == std::string::npos) {
      if (error) *error = "phase '" + item + "' is not of the form 'Name start-end'";
      return false;
    }
    ProfilePhase phase;
    phase.name = trim(item.substr(0, space));
    if (!csv::parseFiniteDouble(item.substr(space + 1, dash - space - 1), &phase.start_s) ||
        !csv::parseFiniteDouble(item.substr(dash + 1), &phase.end_s) || !(phase.end_s > phase.start_s) ||
        phase.name.empty()) {
      if (error) *error = "phase '" + item + "' needs a name and numeric start < end";
      return false;
    }
    if (!phases->empty() && phase.start_s < phases->back().end_s) {
      if (error) *error = "phase '" + item + "' starts before the previous phase ends";
      return false;
    }
    phases->push_back(phase);
  }
  if (phases->empty()) {
    if (error) *error = "no phases listed";
    return false;
  }
  return true;
}

SpeedProfile loadSpeedProfile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open speed profile");
  std::string line, error;
  std::vector<std::string> header, cells;
  std::vector<double> t, v;
  std::vector<ProfilePhase> phases;
  int time_col = -1, speed_col = -1;
  double speed_scale = 1.0;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (trim(line).empty()) continue;
    if (line[0] == '#') {
      const auto tag = line.find("Phases:");
      if (tag != std::string::npos) {
        std::string list = line.substr(tag + 7);
        list = list.substr(0, list.find(". "));  // the sentence ends the list; more text may follow
        if (!parsePhaseList(list, &phases, &error)) throw std::runtime_error(where + error);
      }
      continue;
    }
    if (!csv::splitLine(line, &cells, &error)) throw std::runtime_error(where + error);
    if (header.empty()) {
      header = cells;
      time_col = csv::findColumn(header, "time_s");
      speed_col = csv::findColumn(header, "speed_mps");
      if (speed_col < 0) {
        speed_col = csv::findColumn(header, "speed_kmh");
        speed_scale = 1.0 / 3.6;
      }
      if (time_col < 0 || speed_col < 0)
        throw std::runtime_error(where + "header needs columns time_s and speed_kmh or speed_mps");
      continue;
    }
    double time = 0.0, speed = 0.0;
    if (static_cast<int>(cells.size()) <= std::max(time_col, speed_col) ||
        !csv::parseFiniteDouble(cells[time_col], &time) || !csv::parseFiniteDouble(cells[speed_col], &speed))
      throw std::runtime_error(where + "time_s and speed must be finite numbers");
    if (speed < 0.0) throw std::runtime_error(where + "negative speed " + cells[speed_col]);
    if (!t.empty() && !(time > t.back()))
      throw std::runtime_error(where + "time_s " + cells[time_col] + " does not increase");
    t.push_back(time);
    v.push_back(speed * speed_scale);
  }
  if (t.size() < 2) throw std::runtime_error(path + ": needs at least 2 samples");
  std::string name = path.substr(path.find_last_of('/') + 1);
  name = name.substr(0, name.find_last_of('.'));
  return SpeedProfile(std::move(t), std::move(v), std::move(phases), name);
}

}  // namespace tread_wear
