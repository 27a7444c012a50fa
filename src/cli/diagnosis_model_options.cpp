#include "tread_wear/cli/diagnosis_model_options.h"

#include <exception>

#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace diagnosis {

std::string applyModelOptions(const CommandLine& a, ExtendedModelOptions* m, const std::string& preset_option) {
  if (a.has("orientation") && !parseOrientation(a.get("orientation"), &m->orientation))
    return "--orientation must be literal or flipped, got '" + a.get("orientation") + "'";
  if (a.has(preset_option) && !parsePreset(a.get(preset_option), &m->preset))
    return "--" + preset_option + " must be " + kPresetChoices + ", got '" + a.get(preset_option) + "'";
  return "";
}

std::string applyDiagnosisOptions(const CommandLine& a, DiagnosisOptions* d) {
  const bool automatic = !a.has("preset") || a.get("preset") == "auto";
  if (!automatic) {
    if (!parsePreset(a.get("preset"), &d->model.preset))
      return std::string("--preset must be auto, ") + kPresetChoices + ", got '" + a.get("preset") + "'";
    d->auto_preset = false;
  }
  if (a.has("orientation") && !parseOrientation(a.get("orientation"), &d->model.orientation))
    return "--orientation must be literal or flipped, got '" + a.get("orientation") + "'";
  const char* const options[kNumOutputs] = {"force-noise-model", "wear-noise-model"};
  for (int o = 0; o < kNumOutputs; ++o) {
    const std::string value = a.get(options[o], "auto");
    if (value == "auto") continue;
    NoiseKind kind;
    if (!parseNoiseKind(value, &kind))
      return std::string("--") + options[o] + " must be " + kNoiseModelChoices + ", got '" + value + "'";
    d->noise_kind[o] = kind;
  }
  return "";
}

bool useMechanisms(const CommandLine& a, const char* tool, std::ostream& err, std::optional<MechanismsInUse>* in_use) {
  try {
    in_use->emplace(a.get("mechanisms"));
  } catch (const std::exception& ex) {
    err << tool << ": " << ex.what() << "\n";
    return false;
  }
  return true;
}

}  // namespace diagnosis
}  // namespace tread_wear
