#include "tread_wear/cli/preset_model.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tread_wear {

PresetModel::PresetModel(const TireParams& params, const WearModelOptions& options, const GridSpec* grid)
    : marcher_(params, options) {
  if (grid != nullptr) {
    BrushOptions brush = presetOptions(Preset::kReference, options.orientation);
    brush.grid = *grid;
    custom_ = std::make_unique<BrushWearModel>(params, brush);
    return;
  }
  if (options.preset != Preset::kReference) return;
  ReferenceSolverOptions reference_options;
  reference_options.orientation = options.orientation;
  reference_ = std::make_unique<ReferenceBrushSolver>(params, reference_options);
}

EvalStatus PresetModel::evaluate(const OperatingPoint& op, WearResult* result) {
  if (!reference_ && !custom_) return marcher_.evaluate(op, result);
  if (!op.validate(nullptr)) return EvalStatus::kInvalidInput;
  const double min_speed_mps = marcher_.options().min_speed_mps;
  OperatingPoint slow = op;
  slow.speed_mps = std::max(op.speed_mps, min_speed_mps);
  // WearModel's floor on the rolling speed (locked wheel), so that every path shares its low-speed convention.
  const double min_rolling_speed_mps = marcher_.options().min_rolling_speed_mps;
  const bool floored = slow.rollingSpeed() < min_rolling_speed_mps;
  if (floored) slow.slip_ratio = min_rolling_speed_mps / slow.longitudinalSpeed() - 1.0;
  if (custom_) {
    custom_->evaluate(slow, result);
  } else {
    reference_->evaluate(slow, result);
  }
  if (op.speed_mps >= min_speed_mps && !floored) return EvalStatus::kOk;
  result->wear_rate_kg_per_s = result->wear_rate_kg_per_m * op.speed_mps;
  return EvalStatus::kLowSpeed;
}

PointModel PresetModel::point() {
  return [this](const OperatingPoint& op, WearResult* result) {
    if (evaluate(op, result) == EvalStatus::kInvalidInput) {
      std::string error;
      op.validate(&error);
      throw std::invalid_argument("invalid operating point: " + error);
    }
  };
}

}  // namespace tread_wear
