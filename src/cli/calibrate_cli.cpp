#include "tread_wear/cli/calibrate_cli.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/fitting/calibration.h"
#include "tread_wear/fitting/recording_checks.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/report/calibration_report.h"

namespace tread_wear {
namespace {

const char* const kCalibrateUsage =
    "usage: tread_wear_calibrate --params FILE --runs RUNS.csv [--fit NAMES] [--target T]\n"
    "       [--orientation literal|flipped] [--prior-weight W] [--fy-weight W] [--wear-weight W]\n"
    "       [--grid NX,NY] [--no-cv] [--robust-se] --json OUT.json [--out-params FILE.yaml]\n"
    "Fits named model parameters to a run table (docs/calibration.md) by bounded least squares on error ratios\n"
    "(Eq 24) and cross-validates leaving one condition_id out.\n"
    "  --fit NAMES          comma-separated registry names (default w1,w2,w3,w4); see docs/calibration.md\n"
    "  --target T           auto (default: wear if only w1..w4/T0/sigma_T are fitted, else both),\n"
    "                       side_force, wear or both\n"
    "  --orientation X      literal (default) or flipped slip angle against the track curve\n"
    "  --prior-weight W     Gaussian prior toward the file's values, residual W*(ln p - ln p_file) (default 0)\n"
    "  --fy-weight W        weight of side-force error ratios with --target both (default 1)\n"
    "  --wear-weight W      weight of wear error ratios with --target both (default 1)\n"
    "  --grid NX,NY         brush grid during the fit (default 400,24)\n"
    "  --no-cv              skip leave-one-condition-out cross-validation\n"
    "  --robust-se          HC3 sandwich standard errors (honest when the error-ratio variance differs between\n"
    "                       runs, e.g. additive force noise on small forces) instead of s^2 (J^T J)^-1\n"
    "  --json OUT.json      machine-readable summary (required)\n"
    "  --out-params FILE    write the calibrated parameter file (YAML)\n";

/// A fraction as a percentage with two decimals; "-" when it is not finite (e.g. no cross-validation).
std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f%%", 100.0 * fraction);
  return buffer;
}

}  // namespace

int runCalibrateCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv,
                 {"params", "runs", "fit", "target", "orientation", "prior-weight", "fy-weight", "wear-weight", "grid",
                  "json", "out-params"},
                 {"no-cv", "robust-se"}, &error))
    return usageError(err, "error", error, kCalibrateUsage);
  if (args.help()) {
    out << kCalibrateUsage;
    return 0;
  }
  for (const char* required : {"params", "runs", "json"})
    if (!args.has(required))
      return usageError(err, "error", std::string("--") + required + " is required", kCalibrateUsage);

  CalibrationOptions options;
  try {
    if (args.has("fit")) options.fit = parseParameterList(args.get("fit"));
  } catch (const std::invalid_argument& e) {
    return usageError(err, "error", std::string("--fit: ") + e.what(), kCalibrateUsage);
  }
  if (args.has("target") && !parseTarget(args.get("target"), &options.target))
    return usageError(err, "error", "--target must be auto, side_force, wear or both", kCalibrateUsage);
  if (args.has("orientation") && !parseOrientation(args.get("orientation"), &options.orientation))
    return usageError(err, "error", "--orientation must be literal or flipped, not '" + args.get("orientation") + "'",
                      kCalibrateUsage);
  const std::pair<const char*, double*> numbers[] = {{"prior-weight", &options.prior_weight},
                                                     {"fy-weight", &options.side_force_weight},
                                                     {"wear-weight", &options.wear_weight}};
  for (const auto& [name, target] : numbers)
    if (!args.number(name, target, &error)) return usageError(err, "error", error, kCalibrateUsage);
  if (args.has("grid") && !parseGridSize(args.get("grid"), &options.grid.n_x_steps, &options.grid.n_strips))
    return usageError(err, "error", "--grid must be NX,NY (for example 400,24)", kCalibrateUsage);
  options.cross_validate = !args.has("no-cv");
  options.solver.robust_covariance = args.has("robust-se");
  if (!options.validate(&error)) return usageError(err, "error", error, kCalibrateUsage);

  try {
    const TireParams initial = loadTireParams(args.get("params"));
    RunTable runs = readRunTable(args.get("runs"));
    const std::vector<std::string> warnings = screenSideForceSigns(initial, options.orientation, &runs);
    for (const std::string& w : warnings) err << "warning: " << w << "\n";
    const CalibrationResult result = calibrate(initial, runs, options);
    out << "calibration of " << initial.name << " to " << args.get("runs") << " (" << runs.runs.size()
        << " runs), target " << targetName(result.target) << ", orientation "
        << orientationName(options.orientation) << "\n"
        << result.summary.report() << "RMSER side force: initial " << percent(result.initial.rmser_side_force)
        << ", fitted " << percent(result.fitted.rmser_side_force) << ", leave-one-condition-out "
        << percent(result.cross_validated.rmser_side_force) << "\nRMSER wear rate:  initial "
        << percent(result.initial.rmser_wear) << ", fitted " << percent(result.fitted.rmser_wear)
        << ", leave-one-condition-out " << percent(result.cross_validated.rmser_wear) << "\n";
    std::ofstream json(args.get("json"));
    if (!json) {
      err << "error: cannot write " << args.get("json") << "\n";
      return kExitData;
    }
    json << calibrationJson(result, warnings);
    if (args.has("out-params")) {
      std::ostringstream comment;
      comment << "Calibrated by tread_wear_calibrate: fit " << args.get("runs") << ", parameters";
      for (const std::string& n : options.fit) comment << " " << n;
      comment << ", target " << targetName(result.target) << ", orientation "
              << orientationName(options.orientation) << ", RMSER Fy "
              << percent(result.fitted.rmser_side_force) << " (LOO " << percent(result.cross_validated.rmser_side_force)
              << "), W_r " << percent(result.fitted.rmser_wear) << " (LOO "
              << percent(result.cross_validated.rmser_wear) << ")";
      saveTireParams(result.params, args.get("out-params"), comment.str());
    }
    if (!result.summary.usable) {
      err << "error: the fit is not usable: " << result.summary.message << "\n";
      return kExitData;
    }
  } catch (const std::exception& e) {  // a file, row, parameter or fit that cannot be used
    err << "error: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace tread_wear
