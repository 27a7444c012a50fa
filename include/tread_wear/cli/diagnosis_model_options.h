#pragma once
/// @file diagnosis_model_options.h
/// The model and noise options that tread_wear_diagnose, tread_wear_conceal and tread_wear_diagnosis_harness
/// share, parsed once.

#include <string>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/extensions.h"

namespace tread_wear {
namespace diagnosis {

/// Applies --orientation literal|flipped and --<preset_option> NAME (a preset), when given, to *m; returns the
/// usage error naming the option, or "" when both are absent or valid.
std::string applyModelOptions(const CommandLine& a, ExtendedModelOptions* m, const std::string& preset_option);

/// The diagnosis's own: --orientation, --preset auto|NAME (auto, the default: start at fast and escalate while
/// the solver-error check fails; a name: that preset, its check reported), --force-noise-model and
/// --wear-noise-model auto|additive|relative|combined (auto, the default: selected by AICc). Returns the usage
/// error naming the option, or "".
std::string applyDiagnosisOptions(const CommandLine& a, DiagnosisOptions* d);

}  // namespace diagnosis
}  // namespace tread_wear
