#include "tread_wear/cli/wear_characteristics_cli.h"

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/studies/wear_characteristics.h"

namespace tread_wear {
namespace {

/// W_r in the paper's unit: kg/m -> g/km.
constexpr double kKgPerMToGPerKm = 1e6;

const char* const kCharacteristicsUsage =
    "usage: tread_wear_wear_characteristics --params FILE [--orientation literal|flipped] [--out-dir DIR]\n"
    "Section 4.3 of the paper on the rig's circular track: W_r over side force for several loads (Fig 13) and\n"
    "speeds (Figs 15, 17), the optimal load for a required side force, local optimal speeds and the\n"
    "v0 sin(alpha) = v_m condition, as CSV files in DIR (default docs/figures). Plot: "
    "scripts/plot_wear_characteristics.py\n";

/// A CSV file `name` in `directory`, numbers with 8 significant digits. @throw std::runtime_error
std::ofstream openCsv(const std::string& directory, const std::string& name) {
  std::ofstream f(directory + "/" + name);
  if (!f) throw std::runtime_error("cannot write " + directory + "/" + name);
  f.precision(8);
  return f;
}

/// Writes wc_load_sweep.csv, wc_speed_sweep.csv, wc_wear_at_side_force.csv, wc_optimal_load.csv,
/// wc_optimal_speed.csv and wc_vm_condition.csv (paper units: N, m/s, deg, g/km) into `dir`, for
/// scripts/plot_wear_characteristics.py. @throw std::runtime_error when a file cannot be written.
void writeWearCharacteristicsCsv(const WearCharacteristics& wc, const CharacteristicsOptions& o,
                                 const std::string& dir) {
  auto write_sweeps = [&](const std::string& name, const std::vector<SweepPoint>& points) {
    std::ofstream f = openCsv(dir, name);
    f << "load_n,speed_mps,slip_angle_deg,side_force_n,wear_rate_g_per_km,stick_fraction\n";
    for (const SweepPoint& p : points)
      f << p.load_n << "," << p.speed_mps << "," << p.slip_angle_deg << "," << p.side_force_n << ","
        << p.wear_rate_kg_per_m * kKgPerMToGPerKm << "," << p.stick_fraction << "\n";
  };
  write_sweeps("wc_load_sweep.csv", wc.load_sweeps);
  write_sweeps("wc_speed_sweep.csv", wc.speed_sweeps);

  std::ofstream at = openCsv(dir, "wc_wear_at_side_force.csv");
  at << "side_force_n,variable,load_n,speed_mps,wear_rate_g_per_km\n";
  for (const auto& a : wc.at_side_force) {
    for (size_t i = 0; i < o.loads_n.size(); ++i)
      at << a.side_force_n << ",load," << o.loads_n[i] << "," << o.load_sweep_speed_mps << ","
         << a.wear_by_load_kg_per_m[i] * kKgPerMToGPerKm << "\n";
    for (size_t i = 0; i < o.speeds_mps.size(); ++i)
      at << a.side_force_n << ",speed," << o.speed_sweep_load_n << "," << o.speeds_mps[i] << ","
         << a.wear_by_speed_kg_per_m[i] * kKgPerMToGPerKm << "\n";
  }
  std::ofstream ol = openCsv(dir, "wc_optimal_load.csv");
  ol << "side_force_n,speed_mps,optimal_load_n,wear_rate_g_per_km,at_edge_of_load_grid\n";
  for (const auto& a : wc.at_side_force)
    if (a.optimal_load.found)
      ol << a.side_force_n << "," << o.load_sweep_speed_mps << "," << a.optimal_load.x << ","
         << a.optimal_load.y * kKgPerMToGPerKm << "," << (a.optimal_load.at_edge ? 1 : 0) << "\n";
  std::ofstream os = openCsv(dir, "wc_optimal_speed.csv");
  os << "side_force_n,load_n,local_optimal_speed_mps,wear_rate_g_per_km\n";
  for (const auto& a : wc.at_side_force)
    for (const GridMinimum& m : a.speed_local_minima)
      os << a.side_force_n << "," << o.speed_sweep_load_n << "," << m.x << "," << m.y * kKgPerMToGPerKm << "\n";
  std::ofstream vm = openCsv(dir, "wc_vm_condition.csv");
  vm << "speed_mps,load_n,slip_angle_deg,side_force_n,wear_rate_g_per_km\n";
  for (const auto& c : wc.vm_condition)
    vm << c.speed_mps << "," << o.speed_sweep_load_n << "," << c.slip_angle_deg << "," << c.side_force_n << ","
       << c.wear_rate_kg_per_m * kKgPerMToGPerKm << "\n";
}

}  // namespace

int runWearCharacteristicsCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"params", "orientation", "out-dir"}, {}, &error))
    return usageError(err, "error", error, kCharacteristicsUsage);
  if (args.help()) {
    out << kCharacteristicsUsage;
    return 0;
  }
  if (!args.has("params")) return usageError(err, "error", "--params is required", kCharacteristicsUsage);
  CharacteristicsOptions options;
  if (args.has("orientation") &&
      !parseOrientation(args.get("orientation"), &options.brush.orientation))
    return usageError(err, "error", "--orientation must be literal or flipped", kCharacteristicsUsage);
  const std::string dir = args.get("out-dir", "docs/figures");
  try {
    const TireParams params = loadTireParams(args.get("params"));
    const WearCharacteristics wc = computeWearCharacteristics(params, options);
    writeWearCharacteristicsCsv(wc, options, dir);
    out << "side force [N] -> optimal load [N] (W_r [g/km]) at " << options.load_sweep_speed_mps << " m/s:\n";
    for (const auto& a : wc.at_side_force) {
      out << "  " << a.side_force_n << " -> ";
      if (a.optimal_load.found)
        out << a.optimal_load.x << " (" << a.optimal_load.y * kKgPerMToGPerKm << ")"
            << (a.optimal_load.at_edge ? " at grid edge" : "");
      else
        out << "not reachable";
      out << "; local optimal speeds [m/s]:";
      for (const GridMinimum& m : a.speed_local_minima) out << " " << m.x;
      out << "\n";
    }
    out << "CSV files written to " << dir << "\n";
  } catch (const std::exception& e) {  // a file, row, parameter or fit that cannot be used
    err << "error: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace tread_wear
