#include "tread_wear/ros/node_services.h"

#include <cmath>
#include <sstream>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

std::string field(const char* name, double value, const std::string& constraint) {
  return std::string(name) + " = " + valueText(value) + ": must be " + constraint;
}

/// Why a hypothetical state was rejected; fault is what WheelInputs returned for the input `kind` of state s.
std::string describeInputFault(const tread_wear::WheelState& s, InputKind kind, InputFault fault,
                               const InputLimits& limits) {
  switch (fault) {
    case InputFault::kNone: return "";
    case InputFault::kNotFinite:
      switch (kind) {
        case InputKind::kLoad: return field("load_n", s.load_n, "finite");
        case InputKind::kSpeed: return field("speed_mps", s.speed_mps, "finite");
        case InputKind::kTemperature:
          return field("tread_temperature_c", s.tread_temperature_c, "finite, or NaN for unknown");
        case InputKind::kSlip:
          if (!std::isfinite(s.slip_angle_rad)) return field("slip_angle_rad", s.slip_angle_rad, "finite");
          if (!std::isfinite(s.slip_ratio)) return field("slip_ratio", s.slip_ratio, "finite");
          return field("path_curvature_per_m", s.path_curvature_per_m, "finite");
      }
      break;
    case InputFault::kNegativeLoad: return field("load_n", s.load_n, ">= 0 [N] (0 = wheel off the ground)");
    case InputFault::kLoadTooLarge:
      return field("load_n", s.load_n, "<= limits/max_load_n = " + valueText(limits.max_load_n) + " [N]");
    case InputFault::kSlipAngleOutOfRange:
      return field("slip_angle_rad", s.slip_angle_rad,
                   "within +-limits/max_abs_slip_angle_rad = " + valueText(limits.max_abs_slip_angle_rad) + " [rad]");
    case InputFault::kSlipRatioOutOfRange:
      return field("slip_ratio", s.slip_ratio,
                   "within +-limits/max_abs_slip_ratio = " + valueText(limits.max_abs_slip_ratio) + " and > -1 [-]");
    case InputFault::kCurvatureOutOfRange:
      return field("path_curvature_per_m", s.path_curvature_per_m,
                   "within +-limits/max_abs_path_curvature_per_m = " + valueText(limits.max_abs_path_curvature_per_m) +
                       " [1/m]");
    case InputFault::kNegativeSpeed: return field("speed_mps", s.speed_mps, ">= 0 [m/s]");
    case InputFault::kSpeedTooLarge:
      return field("speed_mps", s.speed_mps, "<= limits/max_speed_mps = " + valueText(limits.max_speed_mps) + " [m/s]");
    case InputFault::kTemperatureOutOfRange:
      return field("tread_temperature_c", s.tread_temperature_c,
                   "in [limits/min_temperature_c, limits/max_temperature_c] = [" + valueText(limits.min_temperature_c) +
                       ", " + valueText(limits.max_temperature_c) + "] [degC], or NaN for unknown");
  }
  return std::string("rejected: ") + inputFaultName(fault);
}

}  // namespace

void evaluateWear(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, Preset configured,
                  const tread_wear::EvaluateWear::Request& req, tread_wear::EvaluateWear::Response* res) {
  WheelPipeline* wheel = findWheel(wheels, req.wheel);
  if (wheel == nullptr) {
    res->success = false;
    res->message = "unknown wheel '" + req.wheel + "'";
    return;
  }
  Preset preset = configured;
  if (!req.preset.empty() && !parsePreset(req.preset, &preset)) {
    res->success = false;
    res->message = "unknown preset '" + req.preset + "' (" + std::string(kPresetChoices) + ")";
    return;
  }
  const InputLimits& limits = wheel->estimatorParams().limits;
  res->preset = presetName(preset);
  res->results.resize(req.states.size());
  for (std::size_t k = 0; k < req.states.size(); ++k) {
    const tread_wear::WheelState& s = req.states[k];
    tread_wear::WheelWearRate& r = res->results[k];
    // The state as the live topics would deliver it, all at one instant, checked in the message's field order.
    WheelInputs inputs(limits);
    const std::pair<InputKind, InputFault> checks[] = {
        {InputKind::kLoad, inputs.setLoad(0.0, s.load_n)},
        {InputKind::kSpeed, inputs.setSpeed(0.0, s.speed_mps)},
        {InputKind::kSlip, inputs.setSlip(0.0, s.slip_angle_rad, s.slip_ratio, s.path_curvature_per_m)},
        {InputKind::kTemperature,
         std::isnan(s.tread_temperature_c) ? InputFault::kNone : inputs.setTemperature(0.0, s.tread_temperature_c)}};
    r.error.clear();
    for (const auto& [kind, fault] : checks)
      if (fault != InputFault::kNone && r.error.empty()) r.error = describeInputFault(s, kind, fault, limits);
    WearResult result;
    const EvalStatus st = r.error.empty() ? wheel->plan(inputs, preset, &result) : EvalStatus::kInvalidInput;
    if (r.error.empty() && st == EvalStatus::kInvalidInput)
      r.error = "outside the wear model's domain";  // only when the configured limits exceed it
    if (!r.error.empty()) {
      r.status = statusCode(WheelStatus::kInvalidInput);
      continue;
    }
    r.status = statusCode(st == EvalStatus::kLowSpeed ? WheelStatus::kLowSpeed : WheelStatus::kOk);
    r.wear_rate_kg_per_m = result.wear_rate_kg_per_m;
    r.wear_rate_kg_per_s = result.wear_rate_kg_per_s;
    r.fx_n = result.fx_n;
    r.fy_n = result.fy_n;
    r.mz_nm = result.mz_nm;
    r.stick_fraction = result.stick_fraction;
    r.slide_fraction = result.slide_fraction;
    r.exact_stick_fraction = result.exact_stick_fraction;
  }
  res->success = true;
}

bool resetWheel(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, double unix_s,
                const tread_wear::ResetWheel::Request& req, tread_wear::ResetWheel::Response* res) {
  WheelPipeline* wheel = findWheel(wheels, req.wheel);
  if (wheel == nullptr || req.tire_id.empty() || req.tire_id.size() > kMaxTireIdLength) {
    res->success = false;
    res->message = wheel == nullptr ? "unknown wheel '" + req.wheel + "'"
                                    : "tire_id must be 1 to " + std::to_string(kMaxTireIdLength) + " characters";
    return false;
  }
  std::string old_tire;
  const WheelAccumulators old = wheel->changeTire(req.tire_id, unix_s, &old_tire);
  res->previous_loss_kg = old.accumulated_loss_kg;
  res->previous_distance_m = old.distance_m;
  std::ostringstream msg;
  msg.precision(9);
  msg << "wheel " << req.wheel << ": tire change " << old_tire << " -> " << req.tire_id << "; the removed tire lost "
      << res->previous_loss_kg << " kg over " << res->previous_distance_m << " m";
  res->message = msg.str();
  res->success = true;
  return true;
}

}  // namespace tread_wear
