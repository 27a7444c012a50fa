#pragma once
/// @file diagnosis_model_options.h
/// The model options that tread_wear_diagnose and tread_wear_conceal share, parsed once.

#include <string>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/diagnosis/extensions.h"

namespace tread_wear {
namespace diagnosis {

/// Applies --orientation literal|flipped and --preset NAME, when given, to *m; returns the usage error naming
/// the option, or "" when both are absent or valid.
std::string applyModelOptions(const CommandLine& a, ExtendedModelOptions* m);

}  // namespace diagnosis
}  // namespace tread_wear
