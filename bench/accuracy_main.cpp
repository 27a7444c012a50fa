/// Accuracy table of the wear-model presets against a fine reference (docs/performance.md).
///   tread_wear_accuracy [--reference marcher|cvode] [--road-params FILE] [--coarse] [--time] [--points FILE.csv]
///                       [--refine LEVEL BUDGET RESOLUTION DAMPING_RATIO] [--entry PERIODS GRADING]
///                       [--entry-strips N]
///                       [--grid NX NY GRADING sine|gauss|panels PASSES TOL]...
/// Prints, for each preset (and each --grid candidate), the maximum error over the Table 3 rig grid
/// (Grosch wheel, both orientations) and the road grid, how many conditions exceed the issue-4 bounds
/// (Fx, Fy, Mz 1%, W_r 2%, stick fraction 0.02) and the worst condition. The reference is
/// the marcher's 'reference' preset (default) or ReferenceBrushSolver (CVODE, default options); where
/// the CVODE solver throws, that condition falls back to the marcher reference and is counted.
/// --points writes every condition's errors (fractions) per candidate and grid to a CSV, with its CPU time
/// under --time (cpu_us; 0 without).
/// --refine sets BrushOptions::refinement of the --grid candidates that follow it (default: off), --entry
/// their entry-transient grid (GridSpec::entry_transit_periods, entry_grading; default: off), --entry-strips
/// its lateral strips (GridSpec::entry_strips; default 0: NY).
/// --time adds, per candidate and grid, the median and p99 over the conditions of the thread CPU time
/// of one evaluation (minimum of 5 repetitions per condition, which filters out most of the noise of a
/// shared machine; tread_wear_bench gives the percentiles over all samples).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "bench_conditions.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"

using namespace tread_wear;

namespace {

struct Candidate {
  std::string name;
  BrushOptions options;
};

double threadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// Evaluates every condition; with cpu_us, also its minimum thread CPU time over 5 repetitions [us].
std::vector<WearResult> evaluateAll(const TireParams& params, const BrushOptions& base,
                                    const std::vector<bench::Condition>& conditions,
                                    std::vector<double>* cpu_us = nullptr) {
  BrushOptions lit = base, flip = base;
  lit.orientation = TurnSlipOrientation::kLiteral;
  flip.orientation = TurnSlipOrientation::kFlipped;
  const BrushWearModel m_lit(params, lit), m_flip(params, flip);
  std::vector<WearResult> out(conditions.size());
  if (cpu_us) cpu_us->assign(conditions.size(), 1e30);
  for (int rep = 0; rep < (cpu_us ? 5 : 1); ++rep)
    for (size_t k = 0; k < conditions.size(); ++k) {
      const double t0 = threadCpuSeconds();
      (conditions[k].orientation == TurnSlipOrientation::kLiteral ? m_lit : m_flip).evaluate(conditions[k].op, &out[k]);
      if (cpu_us) (*cpu_us)[k] = std::min((*cpu_us)[k], 1e6 * (threadCpuSeconds() - t0));
    }
  return out;
}

std::vector<WearResult> cvodeAll(const TireParams& params, const std::vector<bench::Condition>& conditions,
                                 const std::vector<WearResult>& fallback, int* failures) {
  ReferenceSolverOptions lit, flip;
  flip.orientation = TurnSlipOrientation::kFlipped;
  ReferenceBrushSolver s_lit(params, lit), s_flip(params, flip);
  std::vector<WearResult> out(conditions.size());
  for (size_t k = 0; k < conditions.size(); ++k) {
    try {
      (conditions[k].orientation == TurnSlipOrientation::kLiteral ? s_lit : s_flip).evaluate(conditions[k].op, &out[k]);
    } catch (const std::exception& e) {
      ++*failures;
      std::fprintf(stderr, "CVODE reference failed at %s (marcher reference used): %s\n", conditions[k].label.c_str(),
                   e.what());
      out[k] = fallback[k];
    }
  }
  return out;
}

void report(const std::string& name, const std::string& set, const std::vector<bench::Condition>& conditions,
            const std::vector<WearResult>& ref, const std::vector<WearResult>& res, std::vector<double> cpu_us,
            std::FILE* points) {
  SolverErrors worst;
  size_t worst_k[3] = {0, 0, 0};
  double worst_v[3] = {0, 0, 0};
  int over[5] = {0, 0, 0, 0, 0};  // conditions beyond the bounds: Fx, Fy, Mz 1%; W_r 2%; stick 0.02
  for (size_t k = 0; k < conditions.size(); ++k) {
    const SolverErrors e = solverErrors(ref[k], res[k], conditions[k].op.load_n);
    worst.maxWith(e);
    const double ratio[5] = {e.fx / 0.01, e.fy / 0.01, e.mz / 0.01, e.wear / 0.02, e.stick / 0.02};
    for (int q = 0; q < 5; ++q) over[q] += ratio[q] > 1.0;
    if (points) {
      const OperatingPoint& op = conditions[k].op;
      std::fprintf(points, "\"%s\",%s,%s,%g,%g,%g,%g,%g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.3g\n", name.c_str(),
                   set.c_str(), conditions[k].orientation == TurnSlipOrientation::kLiteral ? "literal" : "flipped",
                   op.speed_mps, op.slip_angle_rad / units::kDegree, op.slip_ratio, op.path_curvature_per_m, op.load_n,
                   e.fx, e.fy, e.mz, e.wear, e.stick, e.exact_stick, cpu_us.empty() ? 0.0 : cpu_us[k]);
    }
    const double f = std::max({e.fx, e.fy, e.mz}) / 0.01, w = e.wear / 0.02,
                 a = std::max(e.stick, e.exact_stick) / 0.02;
    const double v[3] = {f, w, a};
    for (int q = 0; q < 3; ++q)
      if (v[q] > worst_v[q]) worst_v[q] = v[q], worst_k[q] = k;
  }
  std::string timing;
  if (!cpu_us.empty()) {
    std::sort(cpu_us.begin(), cpu_us.end());
    char buf[64];
    std::snprintf(buf, sizeof(buf), " | cpu median %.1f us, p99 %.1f us", cpu_us[cpu_us.size() / 2],
                  cpu_us[std::min(cpu_us.size() - 1, static_cast<size_t>(0.99 * cpu_us.size()))]);
    timing = buf;
  }
  std::printf(
      "%-28s %-5s %7.3f%% %7.3f%% %7.3f%% %7.3f%% %7.4f %7.4f | over bounds (Fx Fy Mz W_r stick): %d %d %d %d %d of %zu"
      " | worst F: %s | worst W: %s%s\n",
      name.c_str(), set.c_str(), 100 * worst.fx, 100 * worst.fy, 100 * worst.mz, 100 * worst.wear, worst.stick,
      worst.exact_stick, over[0], over[1], over[2], over[3], over[4], conditions.size(),
      conditions[worst_k[0]].label.c_str(), conditions[worst_k[1]].label.c_str(), timing.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::string road_params_path;  // default: the Grosch wheel (docs/performance.md, "Passenger tire")
  bool coarse = false;
  bool use_cvode = false;
  bool time = false;
  std::string points_path;
  int random_points = 0;
  unsigned random_seed = 1;
  RefinementOptions refine;
  double entry_periods = 0.0, entry_grading = 0.0;
  int entry_strips = 0;
  std::vector<Candidate> candidates;
  for (Preset p : kAllPresets) candidates.push_back({presetName(p), presetOptions(p)});
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--road-params") && i + 1 < argc) {
      road_params_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--reference") && i + 1 < argc) {
      use_cvode = !std::strcmp(argv[++i], "cvode");
    } else if (!std::strcmp(argv[i], "--coarse")) {
      coarse = true;
    } else if (!std::strcmp(argv[i], "--points") && i + 1 < argc) {
      points_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--random") && i + 1 < argc) {
      random_points = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      random_seed = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else if (!std::strcmp(argv[i], "--time")) {
      time = true;
    } else if (!std::strcmp(argv[i], "--refine") && i + 4 < argc) {
      refine = {std::atoi(argv[i + 1]), std::atoi(argv[i + 2]), std::atof(argv[i + 3]), std::atof(argv[i + 4])};
      i += 4;
    } else if (!std::strcmp(argv[i], "--entry") && i + 2 < argc) {
      entry_periods = std::atof(argv[i + 1]);
      entry_grading = std::atof(argv[i + 2]);
      i += 2;
    } else if (!std::strcmp(argv[i], "--entry-strips") && i + 1 < argc) {
      entry_strips = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--grid") && i + 6 < argc) {
      Candidate c;
      c.options.grid.n_x_steps = std::atoi(argv[i + 1]);
      c.options.grid.n_strips = std::atoi(argv[i + 2]);
      c.options.grid.edge_grading = std::atof(argv[i + 3]);
      c.options.grid.lateral_rule = !std::strcmp(argv[i + 4], "gauss")    ? LateralRule::kGaussLegendre
                                    : !std::strcmp(argv[i + 4], "panels") ? LateralRule::kGaussShoulderPanels
                                                                          : LateralRule::kSineMidpoint;
      c.options.grid.entry_transit_periods = entry_periods;
      c.options.grid.entry_grading = entry_grading;
      c.options.grid.entry_strips = entry_strips;
      c.options.refinement = refine;
      c.options.turn_slip_iterations = std::atoi(argv[i + 5]);
      c.options.root_tolerance = std::atof(argv[i + 6]);
      c.name = std::string(argv[i + 1]) + "x" + argv[i + 2] + " g" + argv[i + 3] + " " + argv[i + 4] + " p" +
               argv[i + 5] + " t" + argv[i + 6] +
               (refine.max_level > 0 ? " L" + std::to_string(refine.max_level) : "") +
               (entry_periods > 0.0 ? " e" + std::to_string(entry_grading).substr(0, 4) : "") +
               (entry_periods > 0.0 && entry_strips > 0 ? " ey" + std::to_string(entry_strips) : "");
      candidates.push_back(c);
      i += 6;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--reference marcher|cvode] [--road-params FILE] [--coarse | --random N [--seed S]] "
                   "[--time] [--points FILE.csv] "
                   "[--refine LEVEL BUDGET RESOLUTION DAMPING_RATIO] [--entry PERIODS GRADING] [--entry-strips N] "
                   "[--grid NX NY GRADING sine|gauss|panels PASSES TOL]...\n",
                   argv[0]);
      return 2;
    }
  }
  for (const Candidate& c : candidates) {
    std::string error;
    if (!c.options.validate(&error)) {
      std::fprintf(stderr, "candidate %s: invalid brush options: %s\n", c.name.c_str(), error.c_str());
      return 2;
    }
  }
  const TireParams grosch;
  TireParams road = grosch;
  if (!road_params_path.empty()) road = loadTireParams(road_params_path);
  const double nominal = road.name == grosch.name ? 100.0 : 4000.0;
  const auto rig = bench::rigConditions();
  if (random_points < 0) {
    std::fprintf(stderr, "--random N needs N >= 0\n");
    return 2;
  }
  const auto roadset = random_points > 0 ? bench::randomRoadConditions(nominal, random_points, random_seed)
                                         : bench::roadConditions(nominal, coarse);
  auto ref_rig = evaluateAll(grosch, presetOptions(Preset::kReference), rig);
  auto ref_road = evaluateAll(road, presetOptions(Preset::kReference), roadset);
  int failures = 0;
  if (use_cvode) {
    ref_rig = cvodeAll(grosch, rig, ref_rig, &failures);
    ref_road = cvodeAll(road, roadset, ref_road, &failures);
  }
  const std::string reference_name =
      use_cvode ? "ReferenceBrushSolver (CVODE), " + std::to_string(failures) + " condition(s) fell back to the marcher"
                : "marcher preset 'reference' (1600 x 64)";
  std::printf("reference: %s; road tire: %s (nominal load %.0f N), %zu %sroad and %zu rig conditions\n",
              reference_name.c_str(),
              road.name.c_str(), nominal, roadset.size(),
              random_points > 0 ? ("random (seed " + std::to_string(random_seed) + ") ").c_str() : "", rig.size());
  std::FILE* points = nullptr;
  if (!points_path.empty()) {
    points = std::fopen(points_path.c_str(), "w");
    if (!points) {
      std::fprintf(stderr, "cannot write %s\n", points_path.c_str());
      return 1;
    }
    std::fprintf(points, "candidate,grid,orientation,speed_mps,slip_angle_deg,slip_ratio,path_curvature_per_m,load_n,"
                         "err_fx,err_fy,err_mz,err_wear,err_stick,err_exact_stick,cpu_us\n");
  }
  std::printf("%-28s %-5s %8s %8s %8s %8s %7s %7s\n", "preset", "grid", "Fx", "Fy", "Mz", "W_r", "stick", "exact");
  for (const Candidate& c : candidates) {
    std::vector<double> cpu_rig, cpu_road;
    const bool timed = time && c.name != presetName(Preset::kReference);
    const auto res_rig = evaluateAll(grosch, c.options, rig, timed ? &cpu_rig : nullptr);
    const auto res_road = evaluateAll(road, c.options, roadset, timed ? &cpu_road : nullptr);
    report(c.name, "rig", rig, ref_rig, res_rig, cpu_rig, points);
    report(c.name, "road", roadset, ref_road, res_road, cpu_road, points);
  }
  if (points) std::fclose(points);
  return 0;
}
