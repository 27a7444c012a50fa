#include "tread_wear/core/diagnosis/cli.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tread_wear/core/diagnosis/conceal.h"
#include "tread_wear/core/diagnosis/harness.h"
#include "tread_wear/core/diagnosis/report.h"
#include "tread_wear/core/params_io.h"

namespace tread_wear {
namespace diagnosis {
namespace {

/// --key value options and --flag switches; positional arguments are an error.
struct Args {
  std::map<std::string, std::string> values;
  std::string error;

  Args(int argc, const char* const argv[], const std::vector<std::string>& keys, const std::vector<std::string>& flags) {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (std::find(flags.begin(), flags.end(), a) != flags.end()) {
        values[a] = "1";
      } else if (std::find(keys.begin(), keys.end(), a) != keys.end()) {
        if (i + 1 >= argc) {
          error = "option " + a + " needs a value";
          return;
        }
        values[a] = argv[++i];
      } else {
        error = "unknown argument '" + a + "'";
        return;
      }
    }
  }
  bool has(const std::string& k) const { return values.count(k) > 0; }
  std::string get(const std::string& k, const std::string& d = "") const {
    const auto it = values.find(k);
    return it == values.end() ? d : it->second;
  }
};

bool parseNumber(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0' && std::isfinite(*v);
}

bool parseInt(const std::string& s, long* v) {
  char* end = nullptr;
  *v = std::strtol(s.c_str(), &end, 10);
  return !s.empty() && end && *end == '\0';
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

bool parseOrientation(const std::string& s, TurnSlipOrientation* o) {
  if (s == "literal") *o = TurnSlipOrientation::kLiteral;
  else if (s == "flipped") *o = TurnSlipOrientation::kFlipped;
  else return false;
  return true;
}

/// Applies the options shared by the tools to the model options; returns a usage error or "".
std::string modelOptions(const Args& a, ExtendedModelOptions* m) {
  if (a.has("--orientation") && !parseOrientation(a.get("--orientation"), &m->orientation))
    return "--orientation must be literal or flipped, got '" + a.get("--orientation") + "'";
  if (a.has("--preset") && !parsePreset(a.get("--preset"), &m->preset))
    return "--preset must be fast, standard or reference, got '" + a.get("--preset") + "'";
  return "";
}

const char* const kDiagnoseUsage =
    "usage: tread_wear_diagnose --params FILE (--runs FILE.csv | --bag FILE.bag) --report DIR\n"
    "       [--orientation literal|flipped] [--preset fast|standard] [--candidates a,b,...] [--max-terms N]\n"
    "       [--alpha-locate X] [--alpha-select X] [--seed N] [--plot-script PATH | --no-plots]\n";

}  // namespace

int runDiagnoseCli(int argc, const char* const argv[], const BagReader& bag_reader,
                   const std::string& default_plot_script, std::ostream& out, std::ostream& err) {
  const Args a(argc, argv,
               {"--params", "--runs", "--bag", "--report", "--orientation", "--preset", "--candidates", "--max-terms",
                "--alpha-locate", "--alpha-select", "--seed", "--plot-script"},
               {"--no-plots", "--help"});
  auto usage = [&](const std::string& msg) {
    if (!msg.empty()) err << "tread_wear_diagnose: " << msg << "\n";
    err << kDiagnoseUsage;
    return 2;
  };
  if (a.has("--help")) {
    out << kDiagnoseUsage;
    return 0;
  }
  if (!a.error.empty()) return usage(a.error);
  if (!a.has("--params")) return usage("--params is required");
  if (a.has("--runs") == a.has("--bag")) return usage("give exactly one of --runs and --bag");
  if (!a.has("--report")) return usage("--report is required");
  if (a.has("--bag") && !bag_reader) return usage("--bag: this build has no rosbag support (built without catkin's rosbag)");
  DiagnosisOptions opt;
  std::string e = modelOptions(a, &opt.model);
  if (!e.empty()) return usage(e);
  for (const std::string& name : splitList(a.get("--candidates"))) {
    Term t;
    if (!parseTerm(name, &t)) return usage("--candidates: '" + name + "' is not a library term (tread_wear_conceal --list)");
    opt.candidates.push_back(t);
  }
  long n = 0;
  double x = 0.0;
  if (a.has("--max-terms")) {
    if (!parseInt(a.get("--max-terms"), &n) || n < 0 || n > 4) return usage("--max-terms must be an integer in 0..4");
    opt.max_terms = static_cast<int>(n);
  }
  if (a.has("--alpha-locate")) {
    if (!parseNumber(a.get("--alpha-locate"), &x)) return usage("--alpha-locate must be a number");
    opt.alpha_locate = x;
  }
  if (a.has("--alpha-select")) {
    if (!parseNumber(a.get("--alpha-select"), &x)) return usage("--alpha-select must be a number");
    opt.alpha_select = x;
  }
  if (a.has("--seed")) {
    if (!parseInt(a.get("--seed"), &n) || n < 0) return usage("--seed must be a non-negative integer");
    opt.seed = static_cast<std::uint64_t>(n);
  }
  if (!opt.validate(&e)) return usage(e);

  try {
    const TireParams params = loadTireParams(a.get("--params"));
    const std::string source = a.has("--runs") ? a.get("--runs") : a.get("--bag");
    const RunTable table = a.has("--runs") ? readRunTable(source) : bag_reader(source);
    const DiagnosisData data = buildDiagnosisData(table);
    const DiagnosisResult result = diagnose(params, data, opt);
    const std::filesystem::path dir(a.get("--report"));
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
    const std::string script = a.has("--no-plots") ? "" : a.get("--plot-script", default_plot_script);
    if (!script.empty() && std::filesystem::exists(script)) {
      const std::string cmd = "/usr/bin/python3 '" + script + "' '" + dir.string() + "'";
      if (std::system(cmd.c_str()) == 0) {
        for (const char* p : {"residuals_side_force.png", "residuals_wear.png", "measured_vs_predicted.png"})
          if (std::filesystem::exists(dir / p)) plots.push_back(p);
      } else {
        err << "tread_wear_diagnose: the plot script failed; report written without plots\n";
      }
    } else if (!a.has("--no-plots")) {
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
    out << "held-out RMSER side force " << result.base.cv_rmser[0] << " -> " << result.final_model.cv_rmser[0]
        << ", wear " << result.base.cv_rmser[1] << " -> " << result.final_model.cv_rmser[1] << "\n";
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
      "       tread_wear_conceal --list\n";
  const Args a(argc, argv,
               {"--params", "--effect", "--runs", "--answer", "--magnitude", "--design", "--wear-noise", "--force-noise",
                "--seed", "--orientation", "--preset"},
               {"--list", "--help"});
  auto usage = [&](const std::string& msg) {
    if (!msg.empty()) err << "tread_wear_conceal: " << msg << "\n";
    err << usage_text;
    return 2;
  };
  if (a.has("--help")) {
    out << usage_text;
    return 0;
  }
  if (!a.error.empty()) return usage(a.error);
  if (a.has("--list")) {
    for (const TermInfo& t : termLibrary()) {
      out << t.name << (t.physical ? "" : " (sensor)") << ": " << t.statement << "\n  parameters:";
      for (const TermParameterSpec& p : t.parameters) out << " " << p.name << " [" << p.lower << ", " << p.upper << "]";
      if (t.parameters.empty()) out << " none (a switch)";
      out << "\n  default magnitude: " << defaultMagnitude(t.term) << "\n";
    }
    return 0;
  }
  for (const char* k : {"--params", "--effect", "--runs", "--answer"})
    if (!a.has(k)) return usage(std::string(k) + " is required");
  ConcealSpec spec;
  spec.effect = a.get("--effect");
  spec.design = a.get("--design", spec.design);
  std::string e = modelOptions(a, &spec.model);
  if (!e.empty()) return usage(e);
  double x;
  long n;
  if (a.has("--magnitude")) {
    if (!parseNumber(a.get("--magnitude"), &x)) return usage("--magnitude must be a number");
    spec.magnitude = x;
  }
  if (a.has("--wear-noise")) {
    if (!parseNumber(a.get("--wear-noise"), &x)) return usage("--wear-noise must be a number");
    spec.wear_noise_rsd = x;
  }
  if (a.has("--force-noise")) {
    if (!parseNumber(a.get("--force-noise"), &x)) return usage("--force-noise must be a number");
    spec.side_force_noise_n = x;
  }
  if (a.has("--seed")) {
    if (!parseInt(a.get("--seed"), &n) || n < 0) return usage("--seed must be a non-negative integer");
    spec.seed = static_cast<std::uint64_t>(n);
  }
  if (!spec.validate(&e)) return usage(e);
  try {
    const TireParams params = loadTireParams(a.get("--params"));
    const ConcealCase c = concealEffect(params, spec);
    writeRunTable(c.table, a.get("--runs"),
                  "Generated by tread_wear_conceal (design " + spec.design + ", seed " + std::to_string(spec.seed) +
                      "); the hidden effect is in the answer file, not here.");
    std::ofstream f(a.get("--answer"));
    f << answerJson(c.answer) << "\n";
    if (!f) throw std::runtime_error("cannot write " + a.get("--answer"));
    out << "wrote " << c.table.runs.size() << " runs to " << a.get("--runs") << " and the answer to " << a.get("--answer")
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
      "       [--controls N] [--effects a,b] [--noise 0.05,0.10] [--one-magnitude] [--jobs N] [--seed N] [--csv OUT]\n";
  const Args a(argc, argv,
               {"--params", "--design", "--repeats", "--controls", "--effects", "--noise", "--jobs", "--seed", "--csv"},
               {"--quick", "--one-magnitude", "--help"});
  auto usage = [&](const std::string& msg) {
    if (!msg.empty()) err << "tread_wear_diagnosis_harness: " << msg << "\n";
    err << usage_text;
    return 2;
  };
  if (a.has("--help")) {
    out << usage_text;
    return 0;
  }
  if (!a.error.empty()) return usage(a.error);
  if (!a.has("--params")) return usage("--params is required");
  HarnessOptions h;
  if (a.has("--quick")) {
    // Small mode: the short design, one magnitude, two seeds, one noise level.
    h.design = "small";
    h.repeats = 2;
    h.control_repeats = 4;
    h.wear_noise = {0.05};
    h.two_magnitudes = false;
  }
  h.design = a.get("--design", h.design);
  long n;
  double x;
  if (a.has("--repeats")) {
    if (!parseInt(a.get("--repeats"), &n) || n < 1) return usage("--repeats must be an integer >= 1");
    h.repeats = static_cast<int>(n);
  }
  if (a.has("--controls")) {
    if (!parseInt(a.get("--controls"), &n) || n < 0) return usage("--controls must be an integer >= 0");
    h.control_repeats = static_cast<int>(n);
  }
  if (a.has("--jobs")) {
    if (!parseInt(a.get("--jobs"), &n) || n < 1 || n > 64) return usage("--jobs must be an integer in 1..64");
    h.jobs = static_cast<int>(n);
  }
  if (a.has("--seed")) {
    if (!parseInt(a.get("--seed"), &n) || n < 0) return usage("--seed must be a non-negative integer");
    h.seed = static_cast<std::uint64_t>(n);
  }
  if (a.has("--noise")) {
    h.wear_noise.clear();
    for (const std::string& s : splitList(a.get("--noise"))) {
      if (!parseNumber(s, &x) || x < 0.0 || x > 0.5) return usage("--noise: '" + s + "' must be a wear RSD in [0, 0.5]");
      h.wear_noise.push_back(x);
    }
  }
  if (a.has("--one-magnitude")) h.two_magnitudes = false;
  for (const std::string& name : splitList(a.get("--effects"))) {
    Term t;
    if (name != "none" && !parseTerm(name, &t)) return usage("--effects: '" + name + "' is not a library term");
    if (name != "none") h.effects.push_back(name);
  }
  if (h.design != "table2" && h.design != "small") return usage("--design must be table2 or small");
  try {
    const TireParams params = loadTireParams(a.get("--params"));
    const std::vector<HarnessOutcome> outcomes = runHarness(params, h, &err);
    out << harnessTable(outcomes);
    if (a.has("--csv")) {
      std::ofstream f(a.get("--csv"));
      f << harnessCsv(outcomes);
      if (!f) throw std::runtime_error("cannot write " + a.get("--csv"));
    }
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_diagnosis_harness: " << ex.what() << "\n";
    return 1;
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
