#include "tread_wear/cli/conceal_cli.h"

#include <cmath>
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

int runConcealCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  const char* usage_text =
      "usage: tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]\n"
      "       [--design table2|small|low_slip] [--wear-noise RSD] [--force-noise N] [--seed N]\n"
      "       [--orientation literal|flipped] [--generator-preset fast|standard|fine|reference]\n"
      "       [--information [--preset fast|standard|fine|reference]] [--mechanisms FILE]\n"
      "       tread_wear_conceal --list [--mechanisms FILE]\n";
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "effect", "runs", "answer", "magnitude", "design", "wear-noise", "force-noise",
                "seed", "orientation", "preset", "generator-preset", "mechanisms"},
               {"list", "information"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_conceal", msg, usage_text); };
  if (a.help()) {
    out << usage_text;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  std::optional<MechanismsInUse> mechanisms;  // user-defined terms join the library until the tool returns
  if (!useMechanisms(a, "tread_wear_conceal", err, &mechanisms)) return kExitData;
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
