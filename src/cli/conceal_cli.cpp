#include "tread_wear/cli/conceal_cli.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/cli/diagnosis_model_options.h"
#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/report/diagnosis_report.h"

namespace tread_wear {
namespace diagnosis {

namespace {

const char* const kConcealUsage =
    "usage: tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]\n"
    "       [--design table2|small|low_slip] [--wear-noise RSD] [--force-noise N] [--seed N]\n"
    "       [--orientation literal|flipped] [--generator-preset fast|standard|fine|reference]\n"
    "       [--information [--preset fast|standard|fine|reference]] [--mechanisms FILE]\n"
    "       tread_wear_conceal --params FILE --effect NAME|none --bag DRIVES.bag --segments OUT.csv --answer OUT.json\n"
    "       [--magnitude X] [--orientation literal|flipped] [--generator-preset NAME] [--mechanisms FILE]\n"
    "       [--input-timeout-s S] [--update-rate-hz HZ]\n"
    "       tread_wear_conceal --list [--mechanisms FILE]\n";

/// --bag: the truth of the bag's drive segments (concealInRecordings), one row per wheel and segment.
int concealInBag(const CommandLine& a, const BagReader& bag_reader, std::ostream& out, std::ostream& err) {
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_conceal", msg, kConcealUsage); };
  for (const char* k : {"params", "effect", "segments", "answer"})
    if (!a.has(k)) return usage(std::string("--bag needs --") + k);
  for (const char* k : {"runs", "design", "wear-noise", "force-noise", "seed", "preset"})
    if (a.has(k)) return usage(std::string("--") + k + " does not go with --bag (the caller measures the truth)");
  if (a.has("information")) return usage("--information does not go with --bag");
  if (!bag_reader) return usage("--bag: this build has no rosbag support (built without catkin's rosbag)");
  ExtendedModelOptions model;
  model.preset = Preset::kReference;  // the converged grid, as the designs' truth
  std::string e = applyModelOptions(a, &model, "generator-preset");
  if (!e.empty()) return usage(e);
  double magnitude = std::numeric_limits<double>::quiet_NaN();
  ReplaySettings replay;
  if (!a.number("magnitude", &magnitude, &e) ||
      !a.number("input-timeout-s", &replay.estimator.stale_timeout_s, &e) ||
      !a.number("update-rate-hz", &replay.update_rate_hz, &e))
    return usage(e);
  // As tread_wear_diagnose: a step longer than the timeout is a gap, not a time jump, unless longer than both.
  replay.estimator.max_step_s = std::max(replay.estimator.max_step_s, 2.0 * replay.estimator.stale_timeout_s);
  if (!replay.validate(&e)) return usage(e);
  try {
    const TireParams params = loadTireParams(a.get("params"));
    const RunTable recordings = bag_reader(a.get("bag"), params, replay);
    const ConcealCase c = concealInRecordings(params, recordings, a.get("effect"), magnitude, model);
    const auto wheel_column = std::find(c.table.text_covariate_names.begin(), c.table.text_covariate_names.end(),
                                        "wheel") - c.table.text_covariate_names.begin();
    std::ofstream f(a.get("segments"));
    f << "# tread_wear_conceal --bag " << a.get("bag") << ": true wear of each wheel's segment (effect in "
      << a.get("answer") << ")\nwheel,segment,distance_m,true_wear_rate_kg_per_m,true_mass_loss_kg\n";
    f.precision(17);
    for (const RunRecord& r : c.table.runs)
      f << r.text_covariates.at(static_cast<std::size_t>(wheel_column)) << "," << r.run_order << ","
        << r.drive_distance_m << "," << r.measured_wear_rate_kg_per_m << ","
        << r.measured_wear_rate_kg_per_m * r.drive_distance_m << "\n";
    if (!f) throw std::runtime_error("cannot write " + a.get("segments"));
    std::ofstream answer(a.get("answer"));
    answer << answerJson(c.answer, nullptr);
    if (!answer) throw std::runtime_error("cannot write " + a.get("answer"));
    out << "wrote the truth of " << c.table.runs.size() << " segments to " << a.get("segments") << "\n";
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_conceal: " << ex.what() << "\n";
    return kExitData;
  }
}

}  // namespace

int runConcealCli(int argc, const char* const argv[], const BagReader& bag_reader, std::ostream& out,
                  std::ostream& err) {
  const char* usage_text = kConcealUsage;
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "effect", "runs", "answer", "magnitude", "design", "wear-noise", "force-noise",
                "seed", "orientation", "preset", "generator-preset", "mechanisms", "bag", "segments",
                "input-timeout-s", "update-rate-hz"},
               {"list", "information"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_conceal", msg, usage_text); };
  if (a.help()) {
    out << usage_text;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  std::optional<MechanismsInUse> mechanisms;  // user-defined terms join the library until the tool returns
  if (!useMechanisms(a, "tread_wear_conceal", err, &mechanisms)) return kExitData;
  if (a.has("bag") && !a.has("list")) return concealInBag(a, bag_reader, out, err);
  if (a.has("list")) {
    for (const TermInfo& t : termLibrary()) {
      out << t.name << (t.physical ? "" : " (sensor)") << (t.user ? " (user-defined, " + t.user->where() + ")" : "")
          << ": " << t.statement << "\n  parameters:";
      for (const TermParameterSpec& p : t.parameters)
        out << " " << p.name << " [" << p.lower << ", " << p.upper << "] " << p.unit;
      if (t.parameters.empty()) out << " none (a switch)";
      const double m = defaultMagnitude(t.term);
      out << "\n  default magnitude: ";
      if (std::isnan(m) && t.user) out << "none (give --magnitude)\n";
      else out << m << "\n";
    }
    return 0;
  }
  for (const char* k : {"params", "effect", "runs", "answer"})
    if (!a.has(k)) return usage(std::string("--") + k + " is required");
  ConcealSpec spec;
  spec.effect = a.get("effect");
  spec.design = a.get("design", spec.design);
  if (spec.design == "drives")
    return usage("--design drives needs a fleet (vehicles, profile, checkpoints): tread_wear_diagnosis_harness "
                 "--design drives generates and diagnoses those cases (docs/diagnosis.md, \"Drive-level cases\")");
  // The truth comes from the converged grid unless asked otherwise: finer than any preset a diagnosis chooses, so
  // that the solver's own error is part of every proof (issue 26).
  spec.model.preset = Preset::kReference;
  std::string e = applyModelOptions(a, &spec.model, "generator-preset");
  if (!e.empty()) return usage(e);
  // The diagnosis whose detectability --information computes: the given preset, else auto's first (fast).
  DiagnosisOptions diagnosis;
  diagnosis.model.orientation = spec.model.orientation;
  e = applyModelOptions(a, &diagnosis.model, "preset");
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
    std::optional<Detectability> reference;
    if (information) {
      const DetectabilityOptions d = detectabilityOptions(diagnosis, spec.wear_noise_rsd, spec.side_force_noise_n);
      reference = detectability(params, buildDiagnosisData(c.noise_free), spec.effect, d);
      out << "detectability reference: lambda " << reference->lambda << ", F-test power " << reference->power
          << ", oracle verdicts:";
      for (const OracleVerdict& v : reference->verdicts) out << " " << v.verdict << " " << v.probability;
      out << "\n";
    }
    writeRunTable(c.table, a.get("runs"),
                  "Generated by tread_wear_conceal (design " + spec.design + ", seed " + std::to_string(spec.seed) +
                      "); the hidden effect is in the answer file, not here.");
    std::ofstream f(a.get("answer"));
    f << answerJson(c.answer, reference ? &*reference : nullptr);
    if (!f) throw std::runtime_error("cannot write " + a.get("answer"));
    out << "wrote " << c.table.runs.size() << " runs to " << a.get("runs") << " and the answer to " << a.get("answer")
        << "\n";
    return 0;
  } catch (const std::exception& ex) {
    err << "tread_wear_conceal: " << ex.what() << "\n";
    return kExitData;
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
