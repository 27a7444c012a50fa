#pragma once
/// @file diagnosis_model_options.h
/// The model and noise options that tread_wear_diagnose, tread_wear_conceal and tread_wear_diagnosis_harness
/// share, parsed once.

#include <optional>
#include <ostream>
#include <string>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/diagnosis/user_mechanisms.h"

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

/// --mechanisms FILE: its user-defined terms join the library while *in_use lives (until the tool returns). False
/// after writing "<tool>: <error naming the file and line>" to err (the tool exits with kExitData).
bool useMechanisms(const CommandLine& a, const char* tool, std::ostream& err, std::optional<MechanismsInUse>* in_use);

}  // namespace diagnosis
}  // namespace tread_wear
