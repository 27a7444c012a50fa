#include "tread_wear/cli/cli_tools.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/fitting/run_comparison.h"
#include "tread_wear/io/conditions_csv.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"

namespace tread_wear {
namespace {

constexpr int kExitData = 1;

const char* const kEvalUsage =
    "usage: tread_wear_eval --params FILE [--orientation literal|flipped] [--preset fast|standard|fine|reference]\n"
    "                       [--grid NXxNS] CONDITIONS.csv|-\n"
    "Evaluates the brush wear model (paper Eqs 6-20) at each row of a conditions CSV (or stdin for '-') and\n"
    "writes CSV to stdout: the input columns, then fx_n, fy_n, mz_nm, wear_rate_kg_per_m, wear_rate_kg_per_s,\n"
    "stick_fraction, slide_fraction, exact_stick_fraction.\n"
    "Input columns (SI, ISO 8855 tire axes): speed_mps, slip_angle_rad, slip_ratio, path_radius_m (left turn\n"
    "positive; 0 or empty = straight), load_n, optional tread_temperature_c.\n"
    "  --params FILE        tire parameter file (docs/parameters.md), e.g. config/tires/grosch_wheel.yaml\n"
    "  --orientation X      literal (default): path curvature as given; flipped: curvature negated\n"
    "  --preset NAME        fast, standard (default) or fine: the brush marcher at that grid (docs/performance.md);\n"
    "                       reference: the independent CVODE reference solver (tens of ms per row)\n"
    "  --grid NXxNS         instead of a preset: the brush marcher with NX x-steps and NS lateral strips (e.g.\n"
    "                       3200x16), otherwise the reference preset's options (grading 0.8, sine midpoints,\n"
    "                       3 turn-slip passes, root tolerance 1e-7); for grid-convergence studies\n"
    "Speeds below 0.1 m/s use the low-speed convention of WearModel (wear_model.h). A bad row stops the run\n"
    "with an error naming the row and column; then nothing is written to stdout.\n";

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

/// The model of a preset: the marcher (WearModel) for fast, standard and fine; for reference the independent CVODE
/// solver (reference_solver.h) at its default tolerances; for a custom grid (--grid) the marcher at that grid.
/// All with WearModel's low-speed convention (wear_model.h: speed and rolling-speed floors).
class PresetModel {
 public:
  /// With a grid, the marcher at that grid and the reference preset's other options (the --grid option).
  PresetModel(const TireParams& params, const WearModelOptions& options, const GridSpec* grid = nullptr)
      : marcher_(params, options) {
    if (grid != nullptr) {
      BrushOptions brush = presetOptions(Preset::kReference, options.orientation);
      brush.grid = *grid;
      custom_ = std::make_unique<BrushWearModel>(params, brush);
      return;
    }
    if (options.preset != Preset::kReference) return;
    ReferenceSolverOptions reference_options;
    reference_options.orientation = options.orientation;
    reference_ = std::make_unique<ReferenceBrushSolver>(params, reference_options);
  }

  EvalStatus evaluate(const OperatingPoint& op, WearResult* result) {
    if (!reference_ && !custom_) return marcher_.evaluate(op, result);
    if (!op.validate(nullptr)) return EvalStatus::kInvalidInput;
    const double min_speed_mps = marcher_.options().min_speed_mps;
    OperatingPoint slow = op;
    slow.speed_mps = std::max(op.speed_mps, min_speed_mps);
    // WearModel's floor on the rolling speed (locked wheel), so that every path shares its low-speed convention.
    const double min_rolling_speed_mps = marcher_.options().min_rolling_speed_mps;
    const bool floored = slow.rollingSpeed() < min_rolling_speed_mps;
    if (floored) slow.slip_ratio = min_rolling_speed_mps / slow.longitudinalSpeed() - 1.0;
    if (custom_) {
      custom_->evaluate(slow, result);
    } else {
      reference_->evaluate(slow, result);
    }
    if (op.speed_mps >= min_speed_mps && !floored) return EvalStatus::kOk;
    result->wear_rate_kg_per_s = result->wear_rate_kg_per_m * op.speed_mps;
    return EvalStatus::kLowSpeed;
  }

  PointModel point() {
    return [this](const OperatingPoint& op, WearResult* result) {
      if (evaluate(op, result) == EvalStatus::kInvalidInput) {
        std::string error;
        op.validate(&error);
        throw std::invalid_argument("invalid operating point: " + error);
      }
    };
  }

 private:
  WearModel marcher_;
  std::unique_ptr<ReferenceBrushSolver> reference_;
  std::unique_ptr<BrushWearModel> custom_;
};

std::string fixed(double value, int decimals) {
  if (std::isnan(value)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

}  // namespace

int runEvalCli(int argc, const char* const argv[], std::istream& in, std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"params", "orientation", "preset", "grid"}, {}, &error, 1))
    return usageError(err, "error", error, kEvalUsage);
  if (args.help()) {
    out << kEvalUsage;
    return 0;
  }
  if (!args.has("params")) return usageError(err, "error", "--params FILE is required", kEvalUsage);
  if (args.positional().size() != 1)
    return usageError(err, "error", "give exactly one conditions file (or '-' for stdin)", kEvalUsage);
  WearModelOptions options;
  if (args.has("orientation") && !parseOrientation(args.get("orientation"), &options.orientation))
    return usageError(err, "error", "--orientation must be literal or flipped, not '" + args.get("orientation") + "'",
                      kEvalUsage);
  if (args.has("preset") && !parsePreset(args.get("preset"), &options.preset))
    return usageError(err, "error",
                      std::string("--preset must be ") + kPresetChoices + ", not '" + args.get("preset") + "'",
                      kEvalUsage);
  GridSpec grid = presetOptions(Preset::kReference).grid;
  const bool custom_grid = args.has("grid");
  if (custom_grid) {
    if (args.has("preset")) return usageError(err, "error", "give either --preset or --grid", kEvalUsage);
    if (!parseGridSize(args.get("grid"), &grid.n_x_steps, &grid.n_strips) || !grid.validate(&error))
      return usageError(err, "error", "--grid must be NXxNS with NX >= 4 x-steps and 1..256 strips, not '" +
                                 args.get("grid") + "'", kEvalUsage);
  }
  try {
    const TireParams params = loadTireParams(args.get("params"));
    const std::string& source = args.positional()[0];
    ConditionsTable table;
    if (source == "-") {
      table = readConditions(in, "stdin");
    } else {
      std::ifstream file(source);
      if (!file) {
        err << "error: " << source << ": cannot open the file for reading\n";
        return kExitData;
      }
      table = readConditions(file, source);
    }
    PresetModel model(params, options, custom_grid ? &grid : nullptr);
    std::vector<WearResult> results(table.points.size());
    for (std::size_t i = 0; i < table.points.size(); ++i) {
      const EvalStatus status = model.evaluate(table.points[i], &results[i]);
      if (status == EvalStatus::kInvalidInput) {
        table.points[i].validate(&error);
        err << "error: " << source << ": row " << i + 1 << ": " << error << "\n";
        return kExitData;
      }
      if (status == EvalStatus::kLowSpeed)
        err << "note: row " << i + 1 << ": speed below " << options.min_speed_mps
            << " m/s, low-speed convention applied (wear_model.h)\n";
    }
    std::ostringstream text;  // everything is computed before anything is written
    writeEvaluations(text, table, results);
    out << text.str();
    out.flush();
  } catch (const std::exception& e) {
    err << "error: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

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
