#include "tread_wear/cli/convergence_cli.h"

#include <exception>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/model/units.h"
#include "tread_wear/studies/convergence_study.h"

namespace tread_wear {

namespace {

const char* const kUsage =
    "usage: tread_wear_convergence [--params FILE] [--orientation literal|flipped|both] [--quick] [--extended]\n"
    "Convergence study on the 7 unique Table 3 rig conditions: the reference solver (CVODE, stick/slide\n"
    "events) at its default settings and coarser ones, and the marcher (BDF2, return mapping) at grids\n"
    "50x4 ... 1600x64, against the reference solver with 4x the strips and its tolerance / 100.\n"
    "Prints Markdown tables; errors are relative, in %; times are CPU ms per evaluation.\n"
    "  --params FILE     tire parameter file (default: the built-in Grosch wheel, Table 4)\n"
    "  --orientation X   literal, flipped or both (default)\n"
    "  --quick           fewer rows (reference sweep and marcher grids up to 400x32)\n"
    "  --extended        also the marcher at 3200x256 and 6400x256 (about 1 s per evaluation)\n"
    "  --point FZ_N,ALPHA_DEG,KAPPA,V_MPS,CURVATURE_PER_M\n"
    "                    instead: the marcher's convergence in x alone at this operating point (x steps\n"
    "                    30 ... 1920 against 6400, lateral grid fixed, no substeps), with the observed order\n"
    "  --strips N        lateral strips of --point, shoulder panels (default 24)\n"
    "  --grading G       edge grading of --point's x grids, in [0, 1) (default 0.9)\n"
    "                    (--point takes --orientation literal or flipped; both means literal)\n";

/// "FZ,ALPHA_DEG,KAPPA,V,CURVATURE" as an operating point; false with *error naming what is wrong.
bool parsePoint(const std::string& text, OperatingPoint* op, std::string* error) {
  const std::vector<std::string> items = splitList(text);
  double v[5];
  bool ok = items.size() == 5;
  for (size_t i = 0; ok && i < 5; ++i) ok = csv::parseFiniteDouble(items[i], &v[i]);
  if (!ok) {
    *error = "--point " + text + ": must be five numbers FZ_N,ALPHA_DEG,KAPPA,V_MPS,CURVATURE_PER_M";
    return false;
  }
  op->load_n = v[0];
  op->slip_angle_rad = v[1] * units::kDegree;
  op->slip_ratio = v[2];
  op->speed_mps = v[3];
  op->path_curvature_per_m = v[4];
  std::string why;
  if (!op->validate(&why) || !(op->speed_mps > 0.0)) {
    *error = "--point " + text + ": " + (why.empty() ? "speed must be > 0" : why);
    return false;
  }
  return true;
}

}  // namespace

int runConvergenceCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"params", "orientation", "point", "strips", "grading"}, {"quick", "extended"}, &error)) {
    return usageError(err, "tread_wear_convergence", error, kUsage);
  }
  if (args.help()) {
    out << kUsage;
    return 0;
  }
  const std::string params_path = args.get("params"), orientation = args.get("orientation", "both");
  const bool quick = args.has("quick"), extended = args.has("extended");
  if (orientation != "literal" && orientation != "flipped" && orientation != "both") {
    return usageError(err, "tread_wear_convergence",
                      "--orientation " + orientation + ": must be literal, flipped or both", kUsage);
  }
  OperatingPoint point;
  BrushOptions x_options = xConvergenceOptions();
  const bool x_study = args.has("point");
  if (x_study) {
    if (!parsePoint(args.get("point"), &point, &error) || !args.integer("strips", &x_options.grid.n_strips, &error) ||
        !args.number("grading", &x_options.grid.edge_grading, &error) || !x_options.validate(&error)) {
      return usageError(err, "tread_wear_convergence", error, kUsage);
    }
    if (quick || extended)
      return usageError(err, "tread_wear_convergence", "--quick and --extended belong to the rig study, not --point",
                        kUsage);
  } else if (args.has("strips") || args.has("grading")) {
    return usageError(err, "tread_wear_convergence", "--strips and --grading belong to --point", kUsage);
  }
  try {
    const TireParams params = params_path.empty() ? TireParams() : loadTireParams(params_path);
    if (x_study) {
      x_options.orientation = orientation == "flipped" ? TurnSlipOrientation::kFlipped : TurnSlipOrientation::kLiteral;
      writeXConvergenceStudy(params, x_options, point, out);
      return 0;
    }
    out << "## Convergence study (tread_wear_convergence" << (quick ? " --quick" : "")
        << (extended ? " --extended" : "") << ", params: " << (params_path.empty() ? "built-in Table 4" : params_path)
        << ")\n\n";
    if (orientation != "flipped") writeConvergenceStudy(params, TurnSlipOrientation::kLiteral, quick, extended, out);
    if (orientation != "literal") writeConvergenceStudy(params, TurnSlipOrientation::kFlipped, quick, extended, out);
  } catch (const std::exception& e) {
    err << "tread_wear_convergence: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace tread_wear
