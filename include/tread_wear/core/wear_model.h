#pragma once
/// @file wear_model.h
/// The per-wheel wear model the node, the replay and the planner service call: the brush wear model
/// (brush_wear_model.h) at a resolution preset, with a defined behaviour at low speed and a time budget.
///
/// Low-speed convention: below WearModelOptions::min_speed_mps the model is evaluated at min_speed_mps
/// with the same slips; forces are those of that point, wear per distance W_r is held at its value
/// there, and wear per time is W_r V, so it goes to zero linearly at standstill (no rolling, no sliding).
/// Nothing divides by the speed.

#include <array>
#include <memory>
#include <string>

#include "tread_wear/core/brush_wear_model.h"

namespace tread_wear {

enum class Preset { kFast = 0, kStandard = 1, kReference = 2 };

/// "fast", "standard" or "reference".
const char* presetName(Preset preset);
/// Parses a preset name; false (and *preset untouched) for an unknown name.
bool parsePreset(const std::string& name, Preset* preset);
/// Grid and solver options of a preset.
BrushOptions presetOptions(Preset preset, TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral);

struct WearModelOptions {
  Preset preset = Preset::kStandard;  ///< finest preset wanted
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  double min_speed_mps = 0.1;  ///< low-speed threshold [m/s], > 0

  bool validate(std::string* error) const;
};

enum class EvalStatus {
  kOk = 0,
  kLowSpeed = 1,     ///< speed below min_speed_mps: the low-speed convention applied
  kInvalidInput = 2  ///< the operating point failed validate(); result untouched
};

class WearModel {
 public:
  /// @throw std::invalid_argument naming the field for invalid parameters or options.
  WearModel(const TireParams& params, const WearModelOptions& options);

  /// Evaluates at the active preset; allocates nothing.
  EvalStatus evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields = nullptr) const;

  void setPreset(Preset preset) { active_ = preset; }
  Preset activePreset() const { return active_; }
  const BrushWearModel& solver(Preset preset) const { return *solvers_[static_cast<int>(preset)]; }
  const TireParams& params() const { return params_; }
  const WearModelOptions& options() const { return options_; }

 private:
  TireParams params_;
  WearModelOptions options_;
  Preset active_;
  std::array<std::unique_ptr<BrushWearModel>, 3> solvers_;
};

}  // namespace tread_wear
