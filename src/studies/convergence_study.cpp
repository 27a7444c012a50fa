#include "tread_wear/studies/convergence_study.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <string>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"

namespace tread_wear {

namespace {

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

}  // namespace

void writeConvergenceStudy(const TireParams& params, TurnSlipOrientation orientation, bool quick, bool extended, std::ostream& out) {
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

void writeXConvergenceStudy(const TireParams& params, const BrushOptions& options, const OperatingPoint& op, std::ostream& out) {
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

}  // namespace tread_wear
