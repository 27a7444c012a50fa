#include "tread_wear/core/wear_model.h"

#include <stdexcept>

namespace tread_wear {

const char* presetName(Preset preset) {
  switch (preset) {
    case Preset::kFast: return "fast";
    case Preset::kStandard: return "standard";
    case Preset::kReference: return "reference";
  }
  return "unknown";
}

bool parsePreset(const std::string& name, Preset* preset) {
  for (Preset p : {Preset::kFast, Preset::kStandard, Preset::kReference}) {
    if (name == presetName(p)) {
      *preset = p;
      return true;
    }
  }
  return false;
}

BrushOptions presetOptions(Preset preset, TurnSlipOrientation orientation) {
  BrushOptions o;
  o.orientation = orientation;
  switch (preset) {
    case Preset::kFast: o.grid = {24, 4, 0.8}; o.turn_slip_iterations = 1; break;
    case Preset::kStandard: o.grid = {60, 8, 0.8}; o.turn_slip_iterations = 2; break;
    case Preset::kReference: o.grid = {1600, 64, 0.8}; o.turn_slip_iterations = 3; break;
  }
  return o;
}

bool WearModelOptions::validate(std::string* error) const {
  if (!(min_speed_mps > 0.0)) {
    if (error) *error = "min_speed_mps = " + std::to_string(min_speed_mps) + ": must be > 0";
    return false;
  }
  return true;
}

WearModel::WearModel(const TireParams& params, const WearModelOptions& options)
    : params_(params), options_(options), active_(options.preset) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument("invalid wear model options: " + error);
  for (Preset p : {Preset::kFast, Preset::kStandard, Preset::kReference})
    solvers_[static_cast<int>(p)] = std::make_unique<BrushWearModel>(params, presetOptions(p, options.orientation));
}

EvalStatus WearModel::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) const {
  if (!op.validate(nullptr)) return EvalStatus::kInvalidInput;
  const BrushWearModel& solver = *solvers_[static_cast<int>(active_)];
  if (op.speed_mps >= options_.min_speed_mps) {
    solver.evaluate(op, result, fields);
    return EvalStatus::kOk;
  }
  OperatingPoint slow = op;
  slow.speed_mps = options_.min_speed_mps;
  solver.evaluate(slow, result, fields);
  result->wear_rate_kg_per_s = result->wear_rate_kg_per_m * op.speed_mps;
  return EvalStatus::kLowSpeed;
}

}  // namespace tread_wear
