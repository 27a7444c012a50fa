#include "tread_wear/cli/preset_model.h"

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
  // WearModel's low-speed convention (wear_model.h), so that every path shares it.
  bool low_speed = false;
  const OperatingPoint eval_op = lowSpeedPoint(op, marcher_.options(), &low_speed);
  if (custom_) {
    custom_->evaluate(eval_op, result);
  } else {
    reference_->evaluate(eval_op, result);
  }
  if (!low_speed) return EvalStatus::kOk;
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
