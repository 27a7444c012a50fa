#include "tread_wear/cli/diagnose_cli.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/cli/diagnosis_model_options.h"
#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/parallel_for.h"
#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/fitting/recording_checks.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/report/diagnosis_report.h"

namespace tread_wear {
namespace diagnosis {
namespace {

const char* const kDiagnoseUsage =
    "usage: tread_wear_diagnose --params FILE (--runs FILE.csv | --bag FILE.bag) --report DIR\n"
    "       [--orientation literal|flipped] [--preset auto|fast|standard|fine|reference]\n"
    "       [--force-noise-model auto|additive|relative|combined]\n"
    "       [--wear-noise-model auto|additive|relative|combined]\n"
    "       [--candidates a,b,...] [--mechanisms FILE]\n"
    "       [--max-terms N] [--alpha-locate X] [--alpha-select X] [--detection-power X] [--seed N]\n"
    "       [--plot-script PATH | --no-plots] [--jobs N] [--quiet] [--numerics-sample-cells N]\n"
    "       [--input-timeout-s S] [--update-rate-hz HZ]   (--bag: integration of each wheel's inputs)\n"
    "       [--cv-groups COVARIATE]   hold out whole groups of a categorical covariate (e.g. brand, test)\n"
    "       [--cv-calibrate COVARIATE=LEVEL]   each held-out group's wear scale from its runs at LEVEL\n"
    "                                 (e.g. test=Run-in: a new tyre's one abrasivity from its own run-in)\n";

/// "tread_wear_diagnose: [fast 12.3 s] selection step 1: 4/9 terms, 1,234,567 cells evaluated, about 40 s left in
/// this step".
std::string progressLine(const DiagnosisProgress& p) {
  char line[300];
  int len = std::snprintf(line, sizeof line, "tread_wear_diagnose: [%s %.1f s] %s: %ld cells evaluated",
                          presetName(p.preset), p.elapsed_s, p.step.c_str(), p.cells_evaluated);
  if (p.terms_in_step > 0 && len > 0 && len < static_cast<int>(sizeof line))
    len += std::snprintf(line + len, sizeof line - len, ", %d/%d terms tried", p.terms_tried, p.terms_in_step);
  if (p.step_left_s >= 0.0 && len > 0 && len < static_cast<int>(sizeof line))
    std::snprintf(line + len, sizeof line - len, ", about %.0f s left in this step (then cross-validation)",
                  p.step_left_s);
  return line;
}

/// The verdict on stdout: explanation, residual covariates, empirical terms, close alternatives, held-out errors and,
/// after a `none`, what it rules out.
void printVerdict(const DiagnosisResult& result, std::ostream& out) {
  out << "mismatch_found: " << (result.mismatch_found ? "true" : "false") << "\nexplanation: " << result.explanation
      << "\n";
  for (const std::string& c : result.unexplained_covariates) out << "residual follows: " << c << "\n";
  for (const EmpiricalTerm& t : result.empirical.terms)
    out << "empirical (not physics, no library mechanism matches): " << empiricalSummary(t) << "\n";
  for (const CloseAlternative& c : result.close_alternatives) {
    char line[200];
    std::snprintf(line, sizeof(line), "about as well supported: %s instead of %s (AICc %+.2f)\n", c.model.c_str(),
                  c.instead_of.c_str(), c.delta_aicc);
    out << line;
  }
  char held_out[160];
  std::snprintf(held_out, sizeof(held_out), "held-out RMSER: side force %.2f%% -> %.2f%%, wear %.2f%% -> %.2f%%\n",
                100.0 * result.base.cv_rmser[0], 100.0 * result.final_model.cv_rmser[0],
                100.0 * result.base.cv_rmser[1], 100.0 * result.final_model.cv_rmser[1]);
  out << held_out;
  if (result.explanation == "none")  // what the `none` rules out; every verdict has the table in report.md
    for (const DetectionLimit& l : result.detection_limits) {
      if (std::isnan(l.below) && std::isnan(l.above)) continue;
      char line[200];
      std::snprintf(line, sizeof(line), "would have found (power %g): %s %s", result.detection_power, l.term.c_str(),
                    l.parameter.c_str());
      out << line;
      if (std::isfinite(l.below)) {
        std::snprintf(line, sizeof(line), " <= %.3g", l.below);
        out << line << (std::isfinite(l.above) ? " or" : "");
      }
      if (std::isfinite(l.above)) {
        std::snprintf(line, sizeof(line), " >= %.3g", l.above);
        out << line;
      }
      out << "\n";
    }
}

}  // namespace

int runDiagnoseCli(int argc, const char* const argv[], const BagReader& bag_reader,
                   const std::string& default_plot_script, std::ostream& out, std::ostream& err) {
  CommandLine a;
  std::string parse_error;
  const bool parsed =
      a.parse(argc, argv,
              {"params", "runs", "bag", "report", "orientation", "preset", "candidates", "max-terms", "alpha-locate",
               "alpha-select", "detection-power", "seed", "plot-script", "force-noise-model", "wear-noise-model",
               "mechanisms", "input-timeout-s", "update-rate-hz", "cv-groups", "cv-calibrate", "jobs",
               "numerics-sample-cells"},
              {"no-plots", "quiet"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_diagnose", msg, kDiagnoseUsage); };
  if (a.help()) {
    out << kDiagnoseUsage;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  if (!a.has("params")) return usage("--params is required");
  if (a.has("runs") == a.has("bag")) return usage("give exactly one of --runs and --bag");
  if (!a.has("report")) return usage("--report is required");
  if (a.has("bag") && !bag_reader)
    return usage("--bag: this build has no rosbag support (built without catkin's rosbag)");
  DiagnosisOptions opt;
  std::string e = applyDiagnosisOptions(a, &opt);
  if (!e.empty()) return usage(e);
  std::optional<MechanismsInUse> mechanisms;  // user-defined terms join the library until the tool returns
  if (!useMechanisms(a, "tread_wear_diagnose", err, &mechanisms)) return kExitData;
  for (const std::string& name : splitList(a.get("candidates"))) {
    Term t;
    if (!parseTerm(name, &t))
      return usage("--candidates: '" + name +
                   "' is not a library term (tread_wear_conceal --list [--mechanisms FILE])");
    opt.candidates.push_back(t);
  }
  int seed = static_cast<int>(opt.seed);
  opt.model.jobs = defaultJobs();
  if (!a.integer("jobs", &opt.model.jobs, &e) ||
      !a.integer("numerics-sample-cells", &opt.numerics_sampling.first_sample_cells, &e))
    return usage(e);
  if (opt.model.jobs < 1 || opt.model.jobs > 256) return usage("--jobs must be an integer in 1..256");
  if (!a.has("quiet")) opt.progress = [&err](const DiagnosisProgress& p) { err << progressLine(p) << "\n"; };
  if (!a.integer("max-terms", &opt.max_terms, &e) || !a.number("alpha-locate", &opt.alpha_locate, &e) ||
      !a.number("alpha-select", &opt.alpha_select, &e) || !a.number("detection-power", &opt.detection_power, &e) ||
      !a.integer("seed", &seed, &e))
    return usage(e);
  if (opt.max_terms < 0 || opt.max_terms > 4) return usage("--max-terms must be an integer in 0..4");
  ReplaySettings replay;
  if (!a.number("input-timeout-s", &replay.estimator.stale_timeout_s, &e) ||
      !a.number("update-rate-hz", &replay.update_rate_hz, &e))
    return usage(e);
  // A step longer than the timeout is a gap, not a time jump, unless it is longer than both.
  replay.estimator.max_step_s = std::max(replay.estimator.max_step_s, 2.0 * replay.estimator.stale_timeout_s);
  if (!replay.validate(&e)) return usage(e);
  if (seed < 0) return usage("--seed must be a non-negative integer");
  opt.seed = static_cast<std::uint64_t>(seed);
  if (!opt.validate(&e)) return usage(e);
  const std::string calibration = a.get("cv-calibrate");
  const std::size_t equals = calibration.find('=');
  if (a.has("cv-calibrate") && (equals == std::string::npos || equals == 0 || calibration.back() == '='))
    return usage("--cv-calibrate '" + calibration + "': expected COVARIATE=LEVEL, e.g. test=Run-in");

  try {
    const TireParams params = loadTireParams(a.get("params"));
    const std::string source = a.has("runs") ? a.get("runs") : a.get("bag");
    const auto read_start = std::chrono::steady_clock::now();
    RunTable table = a.has("runs") ? readRunTable(source) : bag_reader(source, params, replay);
    const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    if (!a.has("quiet"))
      err << "tread_wear_diagnose: read " << table.runs.size() << " runs in " << read_seconds << " s\n";
    const std::vector<std::string> warnings = screenSideForceSigns(params, opt.model.orientation, &table);
    for (const std::string& w : warnings) err << "tread_wear_diagnose: warning: " << w << "\n";
    DiagnosisData data = buildDiagnosisData(table);
    if (a.has("cv-groups")) holdOutGroups(&data, a.get("cv-groups"));
    if (a.has("cv-calibrate"))
      calibrateHeldOutGroupsOn(&data, calibration.substr(0, equals), calibration.substr(equals + 1));
    data.warnings = warnings;
    DiagnosisResult result = diagnose(params, data, opt);
    result.timings.insert(result.timings.begin(),
                          {a.has("bag") ? "reading the bag" : "reading the run table", result.preset, read_seconds, 0});
    result.seconds += read_seconds;
    err << "tread_wear_diagnose: " << result.numerics_decision << "\n";
    if (!result.numerics_warning.empty()) err << "tread_wear_diagnose: warning: " << result.numerics_warning << "\n";
    const std::filesystem::path dir(a.get("report"));
    std::filesystem::create_directories(dir);
    {
      std::ofstream f(dir / "diagnosis.json");
      f << diagnosisJson(result, data);
      if (!f) throw std::runtime_error("cannot write " + (dir / "diagnosis.json").string());
    }
    {
      std::ofstream f(dir / "residuals.csv");
      f << residualsCsv(result, data);
      if (!f) throw std::runtime_error("cannot write " + (dir / "residuals.csv").string());
    }
    std::vector<std::string> plots;
    const std::string script = a.has("no-plots") ? "" : a.get("plot-script", default_plot_script);
    if (!script.empty() && std::filesystem::exists(script)) {
      const std::string cmd = "/usr/bin/python3 '" + script + "' '" + dir.string() + "'";
      if (std::system(cmd.c_str()) == 0) {
        for (const char* p : {"residuals_side_force.png", "residuals_wear.png", "measured_vs_predicted.png"})
          if (std::filesystem::exists(dir / p)) plots.push_back(p);
      } else {
        err << "tread_wear_diagnose: the plot script failed; report written without plots\n";
      }
    } else if (!a.has("no-plots")) {
      err << "tread_wear_diagnose: no plot script found ('" << script << "'); report written without plots\n";
    }
    {
      std::ofstream f(dir / "report.md");
      f << diagnosisMarkdown(result, data, source, plots);
      if (!f) throw std::runtime_error("cannot write " + (dir / "report.md").string());
    }
    printVerdict(result, out);
    out << "report: " << (dir / "report.md").string() << "\n";
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_diagnose: " << ex.what() << "\n";
    return kExitData;
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
