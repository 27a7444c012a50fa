#include "tread_wear/cli/diagnosis_model_options.h"

#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace diagnosis {

std::string applyModelOptions(const CommandLine& a, ExtendedModelOptions* m) {
  if (a.has("orientation") && !parseOrientation(a.get("orientation"), &m->orientation))
    return "--orientation must be literal or flipped, got '" + a.get("orientation") + "'";
  if (a.has("preset") && !parsePreset(a.get("preset"), &m->preset))
    return std::string("--preset must be ") + kPresetChoices + ", got '" + a.get("preset") + "'";
  return "";
}

}  // namespace diagnosis
}  // namespace tread_wear
