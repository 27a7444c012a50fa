#include "tread_wear/cli/trajectory_cost_cli.h"

#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/io/wheel_config.h"
#include "tread_wear/planning/candidate_trajectories.h"
#include "tread_wear/planning/wear_map.h"

namespace tread_wear {
namespace {

const char* const kUsage =
    "usage: tread_wear_trajectory_cost --vehicle FILE (--tire FILE | --wheels FILE) [--preset NAME]\n"
    "                                  [--temperature C] [--map [--threads N] | --compare] TRAJECTORIES.csv|-\n"
    "       tread_wear_trajectory_cost --generate N [--seed S]\n"
    "A planner's wear cost of candidate trajectories (docs/planner.md): each sample through the quasi-steady\n"
    "vehicle model to the four wheels' loads and slips, the brush wear model per wheel, the trapezoid rule over\n"
    "time. Writes CSV to stdout, one row per trajectory: trajectory_id, status, samples, duration_s, distance_m,\n"
    "total_wear_kg, wear_per_distance_kg_per_m (1 mg/km = 1e-9 kg/m), wear_<wheel>_kg, stick_<wheel>,\n"
    "slide_<wheel> (time-weighted), message (why a trajectory was not evaluated; empty when ok).\n"
    "Input columns (SI; any order): trajectory_id, time_s (strictly increasing per trajectory), speed_mps (>= 0),\n"
    "accel_mps2, curvature_per_m (CoG path, left turn positive), optional grade_rad (uphill positive; empty\n"
    "column = flat road; the map is for a flat road only: --map fails a trajectory on a grade).\n"
    "  --vehicle FILE     vehicle parameters, e.g. config/vehicle_passenger_car.yaml\n"
    "  --tire FILE        one tire parameter file for all four wheels (docs/parameters.md)\n"
    "  --wheels FILE      or the node's wheel configuration (config/vehicle_wheels.yaml): the tire of each of\n"
    "                     front_left, front_right, rear_left, rear_right, and its preset, orientation, low-speed\n"
    "                     threshold and input limits\n"
    "  --preset NAME      fast, standard (default, or the --wheels file's), fine or reference\n"
    "  --temperature C    tread temperature of every wheel [degC] (used only by tires with temperature_enabled)\n"
    "  --map              evaluate from the wear map over (v, a_x, a_y) (built first: seconds); rows outside it fail\n"
    "  --threads N        threads that build the map (default: the machine's cores)\n"
    "  --compare          both: the direct columns, then map_total_wear_kg and map_relative_error\n"
    "  --generate N       write N seeded candidate trajectories (100 samples, 10 s each; the benchmark's kind)\n"
    "  --seed S           seed of --generate (default 24, the benchmark's)\n"
    "Exit status 0 when every trajectory was evaluated, 1 for bad data (the row's message says why), 2 for bad "
    "usage.\n";

std::string number(double v) { return csv::formatDouble(v); }

void writeHeader(std::ostream& out, bool compare) {
  out << "trajectory_id,status,samples,duration_s,distance_m,total_wear_kg,wear_per_distance_kg_per_m";
  for (const char* what : {"wear_", "stick_", "slide_"})
    for (int i = 0; i < kWheelCount; ++i)
      out << ',' << what << wheelName(i) << (std::string(what) == "wear_" ? "_kg" : "");
  if (compare) out << ",map_total_wear_kg,map_relative_error";
  out << ",message\n";
}

void writeRow(std::ostream& out, const CandidateTrajectory& t, const TrajectoryCost& c, const TrajectoryCost* map) {
  out << csv::quote(t.id) << ',' << costStatusName(c.status) << ',' << t.samples.size() << ',' << number(c.duration_s)
      << ',' << number(c.distance_m) << ',' << number(c.total_wear_kg) << ',' << number(c.wear_per_distance_kg_per_m);
  for (double v : c.wheel_wear_kg) out << ',' << number(v);
  for (double v : c.stick_fraction) out << ',' << number(v);
  for (double v : c.slide_fraction) out << ',' << number(v);
  std::string message = c.message;
  if (map != nullptr) {
    if (map->ok() && c.ok()) {
      const double rel = c.total_wear_kg > 0.0 ? map->total_wear_kg / c.total_wear_kg - 1.0 : 0.0;
      out << ',' << number(map->total_wear_kg) << ',' << number(rel);
    } else {
      out << ",,";
      if (!map->ok()) message += (message.empty() ? "" : "; ") + std::string("map: ") + map->message;
    }
  }
  out << ',' << csv::quote(message) << '\n';
}

int generate(const CommandLine& args, std::ostream& out, std::ostream& err) {
  int count = 0, seed = 24;
  std::string error;
  if (!args.integer("generate", &count, &error) || !args.integer("seed", &seed, &error))
    return usageError(err, "error", error, kUsage);
  CandidateSetParams params;
  params.trajectories = count;
  params.seed = static_cast<std::uint32_t>(seed);
  if (!params.validate(&error)) return usageError(err, "error", "--generate: " + error, kUsage);
  out << "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\n";
  const auto set = generateCandidates(params);
  for (std::size_t t = 0; t < set.size(); ++t)
    for (const TrajectorySample& s : set[t])
      out << "c" << t << ',' << number(s.time_s) << ',' << number(s.speed_mps) << ',' << number(s.accel_mps2) << ','
          << number(s.path_curvature_per_m) << '\n';
  return 0;
}

/// The setup from --wheels (the node's configuration) or --tire, then --preset and --temperature.
bool loadSetup(const CommandLine& args, VehicleWearSetup* setup, std::string* error) {
  try {
    setup->vehicle = loadVehicleParams(args.get("vehicle"));
    if (args.has("wheels")) {
      const NodeConfig config = loadNodeConfigFile(args.get("wheels"));
      std::vector<std::string> names;
      for (const WheelConfig& w : config.wheels) names.push_back(w.name);
      std::array<std::size_t, kWheelCount> index{};
      if (!matchVehicleWheels(names, defaultVehicleWheelNames(), &index, error)) {
        *error = args.get("wheels") + ": " + *error;
        return false;
      }
      for (std::size_t i = 0; i < kWheelCount; ++i) setup->tires[i] = loadTireParams(config.wheels[index[i]].tire_params);
      setup->model = config.model;
      setup->model.time_budget_s = 0.0;
      setup->limits = config.estimator.limits;
    } else {
      setup->tires.fill(loadTireParams(args.get("tire")));
    }
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  double temperature = std::nan("");
  if (!args.number("temperature", &temperature, error)) return false;
  setup->tread_temperature_c.fill(temperature);
  return setup->validate(error);
}

}  // namespace

bool readTrajectoryCsv(std::istream& in, std::vector<CandidateTrajectory>* trajectories, std::string* error) {
  static const char* const kColumns[] = {"trajectory_id", "time_s", "speed_mps", "accel_mps2", "curvature_per_m",
                                         "grade_rad"};
  constexpr int kRequired = 5;  // grade_rad is optional
  std::string line;
  std::vector<std::string> cells;
  int line_number = 0;
  const auto fail = [&](const std::string& what) {
    *error = "line " + std::to_string(line_number) + ": " + what;
    return false;
  };
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.find_first_not_of(" \t\r") != std::string::npos) break;
  }
  if (!csv::splitLine(line, &cells, error)) return fail(*error);
  int column[6];
  for (int c = 0; c < 6; ++c) {
    column[c] = csv::findColumn(cells, kColumns[c]);
    if (column[c] < 0 && c < kRequired) return fail(std::string("missing column ") + kColumns[c]);
  }
  for (const std::string& name : cells) {
    if (name == "grade") return fail("column grade: name it grade_rad (the road grade in radians, uphill positive)");
    bool known = false;
    for (const char* k : kColumns) known = known || name == k;
    if (!known) return fail("unknown column '" + name + "'");
  }
  const std::size_t width = cells.size();
  std::map<std::string, std::size_t> index_of;
  trajectories->clear();
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (!csv::splitLine(line, &cells, error)) return fail(*error);
    if (cells.size() != width)
      return fail(std::to_string(cells.size()) + " cells, the header has " + std::to_string(width));
    const std::string& id = cells[static_cast<std::size_t>(column[0])];
    if (id.empty()) return fail("trajectory_id is empty");
    double v[5] = {0.0, 0.0, 0.0, 0.0, 0.0};  // grade 0 without its column
    for (int c = 1; c < 6; ++c)
      if (column[c] >= 0 && !csv::parseFiniteDouble(cells[static_cast<std::size_t>(column[c])], &v[c - 1]))
        return fail(std::string("column ") + kColumns[c] + ": '" + cells[static_cast<std::size_t>(column[c])] +
                    "' is not a finite number");
    auto found = index_of.find(id);
    if (found == index_of.end()) {
      found = index_of.emplace(id, trajectories->size()).first;
      trajectories->push_back({id, {}});
    }
    (*trajectories)[found->second].samples.push_back({v[0], v[1], v[2], v[3], v[4]});
  }
  return true;
}

int runTrajectoryCostCli(int argc, const char* const argv[], std::istream& in, std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"vehicle", "tire", "wheels", "preset", "temperature", "threads", "generate", "seed"},
                  {"map", "compare"}, &error, 1))
    return usageError(err, "error", error, kUsage);
  if (args.help()) {
    out << kUsage;
    return 0;
  }
  if (args.has("generate")) return generate(args, out, err);
  if (!args.has("vehicle")) return usageError(err, "error", "--vehicle FILE is required", kUsage);
  if (args.has("tire") == args.has("wheels")) return usageError(err, "error", "give --tire or --wheels", kUsage);
  if (args.has("map") && args.has("compare")) return usageError(err, "error", "give --map or --compare", kUsage);
  if (args.positional().size() != 1)
    return usageError(err, "error", "give exactly one trajectory file (or '-' for stdin)", kUsage);
  VehicleWearSetup setup;
  if (!loadSetup(args, &setup, &error)) {
    err << "error: " << error << '\n';
    return kExitData;
  }
  if (args.has("preset") && !parsePreset(args.get("preset"), &setup.model.preset))
    return usageError(err, "error", std::string("--preset must be ") + kPresetChoices + ", not '" + args.get("preset") +
                                        "'", kUsage);
  WearMapParams map_params;
  map_params.build_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!args.integer("threads", &map_params.build_threads, &error)) return usageError(err, "error", error, kUsage);
  if (map_params.build_threads < 1) return usageError(err, "error", "--threads must be >= 1", kUsage);

  std::vector<CandidateTrajectory> trajectories;
  const std::string path = args.positional()[0];
  std::ifstream file;
  if (path != "-") {
    file.open(path);
    if (!file) {
      err << "error: cannot open " << path << '\n';
      return kExitData;
    }
  }
  if (!readTrajectoryCsv(path == "-" ? in : file, &trajectories, &error)) {
    err << "error: " << path << ": " << error << '\n';
    return kExitData;
  }

  const bool use_map = args.has("map"), compare = args.has("compare");
  std::shared_ptr<const WearMap> map;
  std::unique_ptr<TrajectoryCostEvaluator> direct;
  try {
    if (use_map || compare) map = WearMap::build(setup, map_params);
    if (!use_map) direct = std::make_unique<TrajectoryCostEvaluator>(setup);
  } catch (const std::exception& e) {
    err << "error: " << e.what() << '\n';
    return kExitData;
  }
  writeHeader(out, compare);
  int failed = 0;
  for (const CandidateTrajectory& t : trajectories) {
    const TrajectoryCost cost = use_map ? map->evaluate(t.samples.data(), t.samples.size())
                                        : direct->evaluate(t.samples.data(), t.samples.size());
    TrajectoryCost from_map;
    if (compare) from_map = map->evaluate(t.samples.data(), t.samples.size());
    writeRow(out, t, cost, compare ? &from_map : nullptr);
    if (!cost.ok()) {
      ++failed;
      err << "trajectory " << t.id << ": " << costStatusName(cost.status) << ": " << cost.message << '\n';
    }
  }
  if (map) err << "wear map " << fingerprintText(map->fingerprint()) << ": " << map->nodeCount() << " nodes, built in "
               << map->buildTime_s() << " s on " << map_params.build_threads << " thread(s)\n";
  return failed == 0 ? 0 : kExitData;
}

}  // namespace tread_wear
