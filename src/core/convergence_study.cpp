#include "tread_wear/core/convergence_study.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <exception>
#include <iomanip>
#include <string>

#include "tread_wear/core/brush_wear_model.h"
#include "tread_wear/core/command_line.h"
#include "tread_wear/core/csv.h"
#include "tread_wear/core/params_io.h"
#include "tread_wear/core/reference_solver.h"
#include "tread_wear/core/units.h"
#include "tread_wear/core/wear_model.h"

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

struct Sample {
  std::vector<WearResult> results;
  double cpu_ms_per_eval = 0.0;
  long steps = 0;  ///< reference solver only: CVODE steps over all conditions
};

double cpuMs(std::clock_t c0) { return 1e3 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

Sample runReference(const TireParams& params, const ReferenceSolverOptions& options,
                    const std::vector<OperatingPoint>& points) {
  ReferenceBrushSolver solver(params, options);
  Sample sample;
  sample.results.resize(points.size());
  const std::clock_t c0 = std::clock();
  for (size_t i = 0; i < points.size(); ++i) {
    solver.evaluate(points[i], &sample.results[i]);
    sample.steps += solver.lastStats().steps;
  }
  sample.cpu_ms_per_eval = cpuMs(c0) / points.size();
  return sample;
}

Sample runMarcher(const TireParams& params, const BrushOptions& options, const std::vector<OperatingPoint>& points) {
  const BrushWearModel model(params, options);
  Sample sample;
  sample.results.resize(points.size());
  const std::clock_t c0 = std::clock();
  for (size_t i = 0; i < points.size(); ++i) model.evaluate(points[i], &sample.results[i]);
  sample.cpu_ms_per_eval = cpuMs(c0) / points.size();
  return sample;
}

double relErrPercent(double value, double reference) { return 100.0 * (value / reference - 1.0); }

struct MaxErrors {
  double fy = 0, mz = 0, wr = 0;
};

MaxErrors maxErrors(const Sample& s, const Sample& ref) {
  MaxErrors e;
  for (size_t i = 0; i < ref.results.size(); ++i) {
    e.fy = std::max(e.fy, std::fabs(relErrPercent(s.results[i].fy_n, ref.results[i].fy_n)));
    e.mz = std::max(e.mz, std::fabs(relErrPercent(s.results[i].mz_nm, ref.results[i].mz_nm)));
    e.wr = std::max(e.wr, std::fabs(relErrPercent(s.results[i].wear_rate_kg_per_m, ref.results[i].wear_rate_kg_per_m)));
  }
  return e;
}


void study(const TireParams& params, TurnSlipOrientation orientation, bool quick, bool extended, std::ostream& out) {
  const std::vector<OperatingPoint> points = table3RigConditions();
  ReferenceSolverOptions chosen;
  chosen.orientation = orientation;
  ReferenceSolverOptions refined = chosen;
  refined.n_strips = 4 * chosen.n_strips;
  refined.rel_tol = chosen.rel_tol / 100.0;
  const Sample ref = runReference(params, refined, points);
  const Sample base = runReference(params, chosen, points);

  out << "### Orientation: " << orientationName(orientation) << "\n\n";
  out << std::defaultfloat << "Reference solver at its defaults (" << chosen.n_strips << " strips, rel_tol "
      << chosen.rel_tol << ") vs refined (" << refined.n_strips << " strips, rel_tol " << refined.rel_tol << ").\n\n";
  out << "| v0 m/s | alpha deg | Fz N | Fy N | Mz N m | W_r g/km | err Fy % | err Mz % | err W_r % | "
         "stick (v_s<=v_m) | exact stick |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  out << std::fixed;
  for (size_t i = 0; i < points.size(); ++i) {
    const WearResult& r = base.results[i];
    const WearResult& f = ref.results[i];
    out << "| " << std::setprecision(0) << points[i].speed_mps << " | "
        << -points[i].slip_angle_rad / units::kDegree << " | " << points[i].load_n << " | " << std::setprecision(4)
        << r.fy_n << " | " << std::setprecision(6) << r.mz_nm << " | " << std::setprecision(5)
        << r.wear_rate_kg_per_m / units::kGramPerKilometre << " | " << std::setprecision(5)
        << relErrPercent(r.fy_n, f.fy_n) << " | " << relErrPercent(r.mz_nm, f.mz_nm) << " | "
        << relErrPercent(r.wear_rate_kg_per_m, f.wear_rate_kg_per_m) << " | " << std::setprecision(4)
        << r.stick_fraction << " | " << r.exact_stick_fraction << " |\n";
  }
  out << "\nCPU time per evaluation: defaults " << std::setprecision(1) << base.cpu_ms_per_eval << " ms ("
      << base.steps / static_cast<long>(points.size()) << " CVODE steps), refined " << ref.cpu_ms_per_eval
      << " ms (" << ref.steps / static_cast<long>(points.size()) << " steps).\n\n";

  out << "Reference solver settings, max |error| over the 7 conditions vs refined:\n\n";
  out << "| strips | rel_tol | Fy % | Mz % | W_r % | CPU ms/eval |\n|---|---|---|---|---|---|\n";
  struct Setting {
    int strips;
    double rel_tol;
  };
  std::vector<Setting> settings = {{8, 1e-8}, {12, 1e-8}, {16, 1e-8}, {24, 1e-6}, {24, 1e-7}, {24, 1e-8}, {32, 1e-9}};
  if (quick) settings = {{12, 1e-8}, {24, 1e-6}, {24, 1e-8}};
  for (const Setting& s : settings) {
    ReferenceSolverOptions o = chosen;
    o.n_strips = s.strips;
    o.rel_tol = s.rel_tol;
    const Sample sample =
        (s.strips == chosen.n_strips && s.rel_tol == chosen.rel_tol) ? base : runReference(params, o, points);
    const MaxErrors e = maxErrors(sample, ref);
    out << "| " << s.strips << " | " << std::scientific << std::setprecision(0) << s.rel_tol << std::fixed << " | "
        << std::setprecision(5) << e.fy << " | " << e.mz << " | " << e.wr << " | " << std::setprecision(1)
        << sample.cpu_ms_per_eval << " |\n";
  }

  out << "\nMarcher (BrushWearModel, edge_grading 0.8) vs refined reference, max |error| over the 7 conditions:\n\n";
  out << "| n_x_steps x n_strips | Fy % | Mz % | W_r % | CPU ms/eval |\n|---|---|---|---|---|\n";
  std::vector<std::pair<int, int>> grids = {{50, 4}, {100, 8}, {200, 16}, {400, 32}, {800, 64}, {1600, 64}};
  if (quick) grids.resize(4);
  if (extended) {
    grids.emplace_back(3200, 256);
    grids.emplace_back(6400, 256);
  }
  for (const auto& g : grids) {
    BrushOptions o;
    o.grid.n_x_steps = g.first;
    o.grid.n_strips = g.second;
    o.orientation = orientation;
    const Sample sample = runMarcher(params, o, points);
    const MaxErrors e = maxErrors(sample, ref);
    out << "| " << g.first << " x " << g.second << " | " << std::setprecision(4) << e.fy << " | " << e.mz << " | "
        << e.wr << " | " << std::setprecision(2) << sample.cpu_ms_per_eval << " |\n";
  }
  out << "\n";
}

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

void xStudy(const TireParams& params, const BrushOptions& options, const OperatingPoint& op, std::ostream& out) {
  constexpr int kReferenceSteps = 6400;
  const std::vector<int> ladder = {30, 60, 120, 240, 480, 960, 1920};
  const std::vector<XConvergenceRow> rows = xConvergence(params, options, op, ladder, kReferenceSteps);
  out << std::defaultfloat << "### Convergence in x at Fz " << op.load_n << " N, alpha "
      << op.slip_angle_rad / units::kDegree << " deg, kappa " << op.slip_ratio << ", V " << op.speed_mps
      << " m/s, curvature " << op.path_curvature_per_m << " 1/m\n\n"
      << options.grid.n_strips << " shoulder-panel strips, edge grading " << options.grid.edge_grading
      << ", no substeps, against " << kReferenceSteps
      << " x steps on the same strips. Errors as in the accuracy tables (solver_errors.h); order = log2 of the "
         "error ratio of successive rungs.\n\n"
      << "| x steps | Fx % | Fy % | Mz % | W_r % | stick | order Fy | order Mz | order W_r |\n"
      << "|---|---|---|---|---|---|---|---|---|\n";
  // Not defined where an output is exact on every grid (Fy and Mz when straight and symmetric).
  constexpr double kExact = 1e-12;
  for (size_t k = 0; k < rows.size(); ++k) {
    const SolverErrors& e = rows[k].errors;
    out << "| " << rows[k].n_x_steps << std::fixed << std::setprecision(4) << " | " << 100 * e.fx << " | " << 100 * e.fy
        << " | " << 100 * e.mz << " | " << 100 * e.wear << " | " << e.stick;
    out << std::setprecision(2);
    for (double SolverErrors::*f : {&SolverErrors::fy, &SolverErrors::mz, &SolverErrors::wear}) {
      out << " | ";
      const double coarse = k > 0 ? rows[k - 1].errors.*f : 0.0;
      if (coarse > kExact && e.*f > kExact) out << std::log2(coarse / e.*f);
    }
    out << " |\n" << std::defaultfloat;
  }
  out << "\n";
}

}  // namespace

std::vector<OperatingPoint> table3RigConditions() {
  // (v0 [m/s], alpha [deg], Fz [N]): paper Tables 2-3, each unique condition once.
  const double table[7][3] = {{1, 10, 75}, {2, 10, 75}, {3, 10, 75}, {2, 5, 75},
                              {2, 15, 75}, {2, 10, 50}, {2, 10, 100}};
  constexpr double kTrackRadiusM = 0.060;  // Table 1: R_t
  std::vector<OperatingPoint> points;
  for (const auto& row : table) {
    OperatingPoint op;
    op.speed_mps = row[0];
    op.slip_angle_rad = -row[1] * units::kDegree;
    op.load_n = row[2];
    op.path_curvature_per_m = 1.0 / kTrackRadiusM;
    points.push_back(op);
  }
  return points;
}

BrushOptions xConvergenceOptions() {
  BrushOptions o;
  o.grid.lateral_rule = LateralRule::kGaussShoulderPanels;
  o.grid.n_strips = 24;
  o.grid.edge_grading = 0.9;
  o.turn_slip_iterations = 4;
  o.root_tolerance = 1e-8;
  o.max_root_iterations = 80;
  return o;
}

std::vector<XConvergenceRow> xConvergence(const TireParams& params, BrushOptions options, const OperatingPoint& op,
                                          const std::vector<int>& ladder, int reference_n_x_steps) {
  auto evaluate = [&](int n_x_steps) {
    options.grid.n_x_steps = n_x_steps;
    WearResult r;
    BrushWearModel(params, options).evaluate(op, &r);
    return r;
  };
  const WearResult reference = evaluate(reference_n_x_steps);
  std::vector<XConvergenceRow> rows;
  for (int n : ladder) {
    XConvergenceRow row;
    row.n_x_steps = n;
    row.result = evaluate(n);
    row.errors = solverErrors(reference, row.result, op.load_n);
    rows.push_back(row);
  }
  return rows;
}

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
      xStudy(params, x_options, point, out);
      return 0;
    }
    out << "## Convergence study (tread_wear_convergence" << (quick ? " --quick" : "")
        << (extended ? " --extended" : "") << ", params: " << (params_path.empty() ? "built-in Table 4" : params_path)
        << ")\n\n";
    if (orientation != "flipped") study(params, TurnSlipOrientation::kLiteral, quick, extended, out);
    if (orientation != "literal") study(params, TurnSlipOrientation::kFlipped, quick, extended, out);
  } catch (const std::exception& e) {
    err << "tread_wear_convergence: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace tread_wear
