#include "tread_wear/cli/diagnosis_cli.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/diagnosis/conceal.h"
#include "tread_wear/diagnosis/harness.h"
#include "tread_wear/fitting/recording_checks.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/report/diagnosis_report.h"

namespace tread_wear {
namespace diagnosis {
namespace {

/// Applies the options shared by the tools to the model options; returns a usage error or "".
std::string modelOptions(const CommandLine& a, ExtendedModelOptions* m) {
  if (a.has("orientation") && !parseOrientation(a.get("orientation"), &m->orientation))
    return "--orientation must be literal or flipped, got '" + a.get("orientation") + "'";
  if (a.has("preset") && !parsePreset(a.get("preset"), &m->preset))
    return std::string("--preset must be ") + kPresetChoices + ", got '" + a.get("preset") + "'";
  return "";
}

const char* const kDiagnoseUsage =
    "usage: tread_wear_diagnose --params FILE (--runs FILE.csv | --bag FILE.bag) --report DIR\n"
    "       [--orientation literal|flipped] [--preset fast|standard|fine|reference] [--candidates a,b,...]\n"
    "       [--max-terms N] [--alpha-locate X] [--alpha-select X] [--detection-power X] [--seed N]\n"
    "       [--plot-script PATH | --no-plots]\n";

}  // namespace

int runDiagnoseCli(int argc, const char* const argv[], const BagReader& bag_reader,
                   const std::string& default_plot_script, std::ostream& out, std::ostream& err) {
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "runs", "bag", "report", "orientation", "preset", "candidates", "max-terms",
                "alpha-locate", "alpha-select", "detection-power", "seed", "plot-script"},
               {"no-plots"}, &parse_error);
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
  std::string e = modelOptions(a, &opt.model);
  if (!e.empty()) return usage(e);
  for (const std::string& name : splitList(a.get("candidates"))) {
    Term t;
    if (!parseTerm(name, &t))
      return usage("--candidates: '" + name + "' is not a library term (tread_wear_conceal --list)");
    opt.candidates.push_back(t);
  }
  int seed = static_cast<int>(opt.seed);
  if (!a.integer("max-terms", &opt.max_terms, &e) || !a.number("alpha-locate", &opt.alpha_locate, &e) ||
      !a.number("alpha-select", &opt.alpha_select, &e) || !a.number("detection-power", &opt.detection_power, &e) ||
      !a.integer("seed", &seed, &e))
    return usage(e);
  if (opt.max_terms < 0 || opt.max_terms > 4) return usage("--max-terms must be an integer in 0..4");
  if (seed < 0) return usage("--seed must be a non-negative integer");
  opt.seed = static_cast<std::uint64_t>(seed);
  if (!opt.validate(&e)) return usage(e);

  try {
    const TireParams params = loadTireParams(a.get("params"));
    const std::string source = a.has("runs") ? a.get("runs") : a.get("bag");
    RunTable table = a.has("runs") ? readRunTable(source) : bag_reader(source);
    const std::vector<std::string> warnings = screenSideForceSigns(params, opt.model.orientation, &table);
    for (const std::string& w : warnings) err << "tread_wear_diagnose: warning: " << w << "\n";
    DiagnosisData data = buildDiagnosisData(table);
    data.warnings = warnings;
    const DiagnosisResult result = diagnose(params, data, opt);
    const std::filesystem::path dir(a.get("report"));
    std::filesystem::create_directories(dir);
    const nlohmann::json j = diagnosisJson(result, data);
    {
      std::ofstream f(dir / "diagnosis.json");
      f << j.dump(2) << "\n";
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
    out << "mismatch_found: " << (result.mismatch_found ? "true" : "false") << "\nexplanation: " << result.explanation
        << "\n";
    for (const std::string& c : result.unexplained_covariates) out << "residual follows: " << c << "\n";
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
        std::snprintf(line, sizeof(line), "would have found (power %g): %s %s", result.detection_power,
                      l.term.c_str(), l.parameter.c_str());
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
    out << "report: " << (dir / "report.md").string() << "\n";
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_diagnose: " << ex.what() << "\n";
    return 1;
  }
}

int runConcealCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  const char* usage_text =
      "usage: tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]\n"
      "       [--design table2|small] [--wear-noise RSD] [--force-noise N] [--seed N] [--orientation literal|flipped]\n"
      "       [--information]\n"
      "       tread_wear_conceal --list\n";
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "effect", "runs", "answer", "magnitude", "design", "wear-noise", "force-noise",
                "seed", "orientation", "preset"},
               {"list", "information"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_conceal", msg, usage_text); };
  if (a.help()) {
    out << usage_text;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  if (a.has("list")) {
    for (const TermInfo& t : termLibrary()) {
      out << t.name << (t.physical ? "" : " (sensor)") << ": " << t.statement << "\n  parameters:";
      for (const TermParameterSpec& p : t.parameters) out << " " << p.name << " [" << p.lower << ", " << p.upper << "]";
      if (t.parameters.empty()) out << " none (a switch)";
      out << "\n  default magnitude: " << defaultMagnitude(t.term) << "\n";
    }
    return 0;
  }
  for (const char* k : {"params", "effect", "runs", "answer"})
    if (!a.has(k)) return usage(std::string("--") + k + " is required");
  ConcealSpec spec;
  spec.effect = a.get("effect");
  spec.design = a.get("design", spec.design);
  std::string e = modelOptions(a, &spec.model);
  if (!e.empty()) return usage(e);
  int seed = static_cast<int>(spec.seed);
  if (!a.number("magnitude", &spec.magnitude, &e) || !a.number("wear-noise", &spec.wear_noise_rsd, &e) ||
      !a.number("force-noise", &spec.side_force_noise_n, &e) || !a.integer("seed", &seed, &e))
    return usage(e);
  if (seed < 0) return usage("--seed must be a non-negative integer");
  spec.seed = static_cast<std::uint64_t>(seed);
  if (!spec.validate(&e)) return usage(e);
  const bool information = a.has("information");
  if (information && !(spec.wear_noise_rsd > 0.0 && spec.side_force_noise_n > 0.0))
    return usage("--information needs --wear-noise and --force-noise > 0 (the reference is in units of the noise)");
  try {
    const TireParams params = loadTireParams(a.get("params"));
    const ConcealCase c = concealEffect(params, spec);
    nlohmann::json answer = answerJson(c.answer);
    if (information) {
      // The settings the harness uses for the same case: a default diagnosis of this model.
      DiagnosisOptions diagnosis;
      diagnosis.model = spec.model;
      const DetectabilityOptions d = detectabilityOptions(diagnosis, spec.wear_noise_rsd, spec.side_force_noise_n);
      const Detectability reference = detectability(params, buildDiagnosisData(c.noise_free), spec.effect, d);
      answer["detectability"] = detectabilityJson(reference);
      out << "detectability reference: lambda " << reference.lambda << ", F-test power " << reference.power
          << ", oracle verdicts:";
      for (const OracleVerdict& v : reference.verdicts) out << " " << v.verdict << " " << v.probability;
      out << "\n";
    }
    writeRunTable(c.table, a.get("runs"),
                  "Generated by tread_wear_conceal (design " + spec.design + ", seed " + std::to_string(spec.seed) +
                      "); the hidden effect is in the answer file, not here.");
    std::ofstream f(a.get("answer"));
    f << answer.dump(2) << "\n";
    if (!f) throw std::runtime_error("cannot write " + a.get("answer"));
    out << "wrote " << c.table.runs.size() << " runs to " << a.get("runs") << " and the answer to " << a.get("answer")
        << "\n";
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_conceal: " << ex.what() << "\n";
    return 1;
  }
}

int runHarnessCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  const char* usage_text =
      "usage: tread_wear_diagnosis_harness --params FILE [--quick] [--design table2|small] [--repeats N]\n"
      "       [--controls N] [--effects a,b] [--noise 0.05,0.10] [--one-magnitude] [--information] [--alpha-select X]\n"
      "       [--jobs N] [--seed N] [--csv OUT]\n";
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "design", "repeats", "controls", "effects", "noise", "jobs", "seed", "csv", "alpha-select"},
               {"quick", "one-magnitude", "information"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_diagnosis_harness", msg, usage_text); };
  if (a.help()) {
    out << usage_text;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  if (!a.has("params")) return usage("--params is required");
  HarnessOptions h;
  if (a.has("quick")) {
    // Small mode: the short design, one magnitude, two seeds, one noise level.
    h.design = "small";
    h.repeats = 2;
    h.control_repeats = 4;
    h.wear_noise = {0.05};
    h.two_magnitudes = false;
  }
  h.design = a.get("design", h.design);
  std::string e;
  int seed = static_cast<int>(h.seed);
  if (!a.integer("repeats", &h.repeats, &e) || !a.integer("controls", &h.control_repeats, &e) ||
      !a.integer("jobs", &h.jobs, &e) || !a.integer("seed", &seed, &e) ||
      !a.number("alpha-select", &h.diagnosis.alpha_select, &e))
    return usage(e);
  if (!h.diagnosis.validate(&e)) return usage(e);
  if (h.repeats < 1) return usage("--repeats must be an integer >= 1");
  if (h.control_repeats < 0) return usage("--controls must be an integer >= 0");
  if (h.jobs < 1 || h.jobs > 64) return usage("--jobs must be an integer in 1..64");
  if (seed < 0) return usage("--seed must be a non-negative integer");
  h.seed = static_cast<std::uint64_t>(seed);
  if (a.has("noise")) {
    h.wear_noise.clear();
    for (const std::string& item : splitList(a.get("noise"))) {
      double x = 0.0;
      if (!csv::parseFiniteDouble(item, &x) || x < 0.0 || x > 0.5)
        return usage("--noise: '" + item + "' must be a wear RSD in [0, 0.5]");
      h.wear_noise.push_back(x);
    }
  }
  if (a.has("one-magnitude")) h.two_magnitudes = false;
  h.information = a.has("information");
  if (h.information && std::find(h.wear_noise.begin(), h.wear_noise.end(), 0.0) != h.wear_noise.end())
    return usage("--information needs every --noise level > 0 (the reference is measured in units of the noise)");
  for (const std::string& name : splitList(a.get("effects"))) {
    Term t;
    if (name != "none" && !parseTerm(name, &t)) return usage("--effects: '" + name + "' is not a library term");
    if (name != "none") h.effects.push_back(name);
  }
  if (h.design != "table2" && h.design != "small") return usage("--design must be table2 or small");
  try {
    const TireParams params = loadTireParams(a.get("params"));
    const std::vector<HarnessOutcome> outcomes = runHarness(params, h, &err);
    out << harnessTable(outcomes);
    if (a.has("csv")) {
      std::ofstream f(a.get("csv"));
      f << harnessCsv(outcomes);
      if (!f) throw std::runtime_error("cannot write " + a.get("csv"));
    }
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_diagnosis_harness: " << ex.what() << "\n";
    return 1;
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
