#include "tread_wear/cli/eval_cli.h"

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/cli/preset_model.h"
#include "tread_wear/io/conditions_csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

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

}  // namespace tread_wear
