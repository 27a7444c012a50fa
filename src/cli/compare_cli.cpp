#include "tread_wear/cli/compare_cli.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/cli/preset_model.h"
#include "tread_wear/fitting/run_comparison.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

const char* const kCompareUsage =
    "usage: tread_wear_compare --params FILE --runs RUNS.csv [--orientation literal|flipped|both]\n"
    "                          [--preset fast|standard|fine|reference] [--csv OUT.csv]\n"
    "Compares the model with measured runs (run table v1, docs/run_table.md): per run the conditions, measured\n"
    "and predicted side force [N] and wear rate [g/km] with error ratios (Eq 24), then RMSER per orientation.\n"
    "Runs with load_std_n are predicted as the Eq 23 average over 10 N load bins.\n"
    "  --params FILE        tire parameter file (docs/parameters.md)\n"
    "  --runs FILE          run table, e.g. data/paper/table3_runs.csv\n"
    "  --orientation X      literal, flipped or both (default both)\n"
    "  --preset NAME        fast, standard or fine: the brush marcher at that grid; reference (default): the\n"
    "                       independent CVODE reference solver (reference_solver.h)\n"
    "  --csv OUT.csv        also write the per-run comparison in SI to OUT.csv\n";

/// `value` with `decimals` decimals for the report table; "-" for NaN (a run without that measurement).
std::string fixed(double value, int decimals) {
  if (std::isnan(value)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

}  // namespace

int runCompareCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"params", "runs", "orientation", "preset", "csv"}, {}, &error))
    return usageError(err, "error", error, kCompareUsage);
  if (args.help()) {
    out << kCompareUsage;
    return 0;
  }
  if (!args.has("params") || !args.has("runs"))
    return usageError(err, "error", "--params FILE and --runs FILE are required", kCompareUsage);
  std::vector<TurnSlipOrientation> orientations = {TurnSlipOrientation::kLiteral, TurnSlipOrientation::kFlipped};
  if (args.has("orientation") && args.get("orientation") != "both") {
    TurnSlipOrientation o;
    if (!parseOrientation(args.get("orientation"), &o))
      return usageError(err, "error", "--orientation must be literal, flipped or both", kCompareUsage);
    orientations = {o};
  }
  Preset preset = Preset::kReference;
  if (args.has("preset") && !parsePreset(args.get("preset"), &preset))
    return usageError(err, "error", std::string("--preset must be ") + kPresetChoices, kCompareUsage);
  try {
    const TireParams params = loadTireParams(args.get("params"));
    const RunTable table = readRunTable(args.get("runs"));
    std::ostringstream report;
    std::ostringstream csv_text;
    csv_text << "orientation,run,condition_id,speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,load_std_n,"
                "measured_side_force_n,predicted_side_force_n,side_force_error_ratio,measured_wear_rate_kg_per_m,"
                "predicted_wear_rate_kg_per_m,wear_error_ratio\n";
    report << "params: " << args.get("params") << " (" << params.name << "), runs: " << args.get("runs")
           << ", preset: " << presetName(preset) << "\n";
    std::vector<std::string> summary;
    for (TurnSlipOrientation orientation : orientations) {
      WearModelOptions options;
      options.preset = preset;
      options.orientation = orientation;
      PresetModel model(params, options);
      const RunComparison c = compareRuns(table, model.point());
      report << "\norientation: " << orientationName(orientation) << "\n";
      char line[512];
      std::snprintf(line, sizeof line, "%3s  %-22s %7s %8s %7s %5s | %8s %8s %7s | %8s %8s %7s\n", "run", "condition",
                    "v0[m/s]", "alpha[deg]", "Fz[N]", "bins", "Fy_meas", "Fy_pred", "err[%]", "Wr_meas", "Wr_pred",
                    "err[%]");
      report << line;
      std::snprintf(line, sizeof line, "%3s  %-22s %7s %8s %7s %5s | %8s %8s %7s | %8s %8s %7s\n", "", "", "", "", "",
                    "", "[N]", "[N]", "", "[g/km]", "[g/km]", "");
      report << line;
      for (std::size_t i = 0; i < table.runs.size(); ++i) {
        const RunRecord& run = table.runs[i];
        const RunPrediction& p = c.runs[i];
        const double radius_m = run.op.path_curvature_per_m == 0.0 ? 0.0 : 1.0 / run.op.path_curvature_per_m;
        std::snprintf(line, sizeof line, "%3zu  %-22s %7s %8s %7s %5d | %8s %8s %7s | %8s %8s %7s\n", i + 1,
                      run.condition_id.substr(0, 22).c_str(), fixed(run.op.speed_mps, 2).c_str(),
                      fixed(run.op.slip_angle_rad / units::kDegree, 2).c_str(), fixed(run.op.load_n, 1).c_str(),
                      p.load_bins, fixed(run.measured_side_force_n, 2).c_str(), fixed(p.side_force_n, 2).c_str(),
                      fixed(100.0 * p.side_force_error_ratio, 1).c_str(),
                      fixed(run.measured_wear_rate_kg_per_m / units::kGramPerKilometre, 3).c_str(),
                      fixed(p.wear_rate_kg_per_m / units::kGramPerKilometre, 3).c_str(),
                      fixed(100.0 * p.wear_error_ratio, 1).c_str());
        report << line;
        auto cell = [](double v) { return std::isnan(v) ? std::string() : csv::formatDouble(v); };
        csv_text << orientationName(orientation) << "," << i + 1 << "," << csv::quote(run.condition_id) << ","
                 << cell(run.op.speed_mps) << "," << cell(run.op.slip_angle_rad) << "," << cell(run.op.slip_ratio)
                 << "," << cell(radius_m) << "," << cell(run.op.load_n) << "," << cell(run.load_std_n) << ","
                 << cell(run.measured_side_force_n) << "," << cell(p.side_force_n) << ","
                 << cell(p.side_force_error_ratio) << "," << cell(run.measured_wear_rate_kg_per_m) << ","
                 << cell(p.wear_rate_kg_per_m) << "," << cell(p.wear_error_ratio) << "\n";
      }
      std::snprintf(line, sizeof line, "RMSER %-8s Fy = %s %% (%d runs), W_r = %s %% (%d runs)",
                    orientationName(orientation), fixed(100.0 * c.rmser_side_force, 2).c_str(), c.n_side_force,
                    fixed(100.0 * c.rmser_wear, 2).c_str(), c.n_wear);
      report << line << "\n";
      summary.push_back(line);
    }
    if (summary.size() > 1) {
      report << "\n";
      for (const std::string& s : summary) report << s << "\n";
    }
    if (args.has("csv")) {
      std::ofstream file(args.get("csv"));
      file << csv_text.str();
      file.flush();
      if (!file) {
        err << "error: " << args.get("csv") << ": cannot write\n";
        return kExitData;
      }
    }
    out << report.str();
    out.flush();
  } catch (const std::exception& e) {
    err << "error: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace tread_wear
