#include "tread_wear/cli/diagnosis_harness_cli.h"

#include <algorithm>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/cli/diagnosis_model_options.h"
#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/proving/harness.h"

namespace tread_wear {
namespace diagnosis {

int runHarnessCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  const char* usage_text =
      "usage: tread_wear_diagnosis_harness --params FILE [--quick] [--design table2|small|low_slip|drives]\n"
      "       [--repeats N] [--controls N] [--effects a,b] [--noise 0.05,0.10] [--one-magnitude] [--information]\n"
      "       [--alpha-select X] [--jobs N] [--seed N] [--csv OUT] [--preset auto|fast|standard|fine|reference]\n"
      "       [--generator-preset fast|standard|fine|reference]\n"
      "       [--force-noise-model auto|additive|relative|combined]\n"
      "       [--wear-noise-model auto|additive|relative|combined] [--mechanisms FILE]\n"
      "       [--out-of-library]   (diagnose with the built-in library less the hidden term: scores empirical terms)\n"
      "  design drives (docs/diagnosis.md, \"Drive-level cases\"; effects thermal_wear and rough_road):\n"
      "       --vehicles FILE[=MASS_KG],...  vehicle parameter files (=MASS_KG: that mass instead of the file's, a\n"
      "                  variant named <name>_<mass>kg)  --profile SPEED.csv  the cycle (data/wltc_class3b.csv)\n"
      "       [--checkpoints 4] [--segment-km 3000] [--rate-hz 10] [--gauge-sigma-mm 0]\n";
  CommandLine a;
  std::string parse_error;
  const bool parsed = a.parse(argc, argv,
               {"params", "design", "repeats", "controls", "effects", "noise", "jobs", "seed", "csv", "alpha-select",
                "preset", "generator-preset", "force-noise-model", "wear-noise-model", "mechanisms", "vehicles",
                "profile", "checkpoints", "segment-km", "rate-hz", "gauge-sigma-mm"},
               {"quick", "one-magnitude", "information", "out-of-library"}, &parse_error);
  auto usage = [&](const std::string& msg) { return usageError(err, "tread_wear_diagnosis_harness", msg, usage_text); };
  if (a.help()) {
    out << usage_text;
    return 0;
  }
  if (!parsed) return usage(parse_error);
  if (!a.has("params")) return usage("--params is required");
  std::optional<MechanismsInUse> mechanisms;  // user-defined terms join the library until the tool returns
  if (!useMechanisms(a, "tread_wear_diagnosis_harness", err, &mechanisms)) return kExitData;
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
  std::string e = applyDiagnosisOptions(a, &h.diagnosis);
  if (!e.empty()) return usage(e);
  if (a.has("generator-preset") && !parsePreset(a.get("generator-preset"), &h.generator_preset))
    return usage(std::string("--generator-preset must be ") + kPresetChoices + ", got '" + a.get("generator-preset") +
                 "'");
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
  h.out_of_library = a.has("out-of-library");
  if (h.information && std::find(h.wear_noise.begin(), h.wear_noise.end(), 0.0) != h.wear_noise.end())
    return usage("--information needs every --noise level > 0 (the reference is measured in units of the noise)");
  for (const std::string& name : splitList(a.get("effects"))) {
    Term t;
    if (name != "none" && !parseTerm(name, &t) && !(h.design == "drives" && name == kRoughRoadEffect))
      return usage("--effects: '" + name + "' is not a library term" +
                   (h.design == "drives" ? std::string(" or ") + kRoughRoadEffect : std::string()));
    if (name != "none") h.effects.push_back(name);
  }
  if (h.design != "table2" && h.design != "small" && h.design != "low_slip" && h.design != "drives")
    return usage("--design must be table2, small, low_slip or drives");
  const bool drives = h.design == "drives";
  for (const char* option : {"vehicles", "profile", "checkpoints", "segment-km", "rate-hz", "gauge-sigma-mm"})
    if (!drives && a.has(option)) return usage(std::string("--") + option + " is an option of --design drives only");
  if (drives && (!a.has("vehicles") || !a.has("profile")))
    return usage("--design drives needs --vehicles and --profile");
  double segment_km = h.fleet.segment_distance_m / 1e3, gauge_mm = h.fleet.depth_gauge_sigma_m * 1e3;
  if (!a.integer("checkpoints", &h.fleet.checkpoints, &e) || !a.number("segment-km", &segment_km, &e) ||
      !a.number("rate-hz", &h.fleet.update_rate_hz, &e) || !a.number("gauge-sigma-mm", &gauge_mm, &e))
    return usage(e);
  h.fleet.segment_distance_m = segment_km * 1e3;
  h.fleet.depth_gauge_sigma_m = gauge_mm * 1e-3;
  try {
    if (drives) {
      for (const std::string& item : splitList(a.get("vehicles"))) {
        const std::size_t eq = item.find('=');
        VehicleParams v = loadVehicleParams(item.substr(0, eq));
        if (eq != std::string::npos) {
          double mass = 0.0;
          if (!csv::parseFiniteDouble(item.substr(eq + 1), &mass))
            return usage("--vehicles: '" + item + "' must be FILE or FILE=MASS_KG");
          v.mass_kg = mass;
          v.name += "_" + item.substr(eq + 1) + "kg";
        }
        h.fleet.vehicles.push_back(v);
      }
      h.fleet.profile = std::make_shared<const SpeedProfile>(loadSpeedProfile(a.get("profile")));
      if (!h.fleet.validate(&e)) return usage(e);
    }
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
    return kExitData;
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
