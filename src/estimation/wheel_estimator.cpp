#include "tread_wear/estimation/wheel_estimator.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {

const char* inputKindName(InputKind kind) {
  switch (kind) {
    case InputKind::kLoad: return "load";
    case InputKind::kSlip: return "slip";
    case InputKind::kSpeed: return "speed";
    case InputKind::kTemperature: return "tread_temperature";
  }
  return "unknown";
}

const char* inputFaultName(InputFault fault) {
  switch (fault) {
    case InputFault::kNone: return "none";
    case InputFault::kNotFinite: return "not_finite";
    case InputFault::kNegativeLoad: return "negative_load";
    case InputFault::kLoadTooLarge: return "load_too_large";
    case InputFault::kSlipAngleOutOfRange: return "slip_angle_out_of_range";
    case InputFault::kSlipRatioOutOfRange: return "slip_ratio_out_of_range";
    case InputFault::kCurvatureOutOfRange: return "curvature_out_of_range";
    case InputFault::kNegativeSpeed: return "negative_speed";
    case InputFault::kSpeedTooLarge: return "speed_too_large";
    case InputFault::kTemperatureOutOfRange: return "temperature_out_of_range";
  }
  return "unknown";
}

const char* wheelStatusName(WheelStatus status) {
  switch (status) {
    case WheelStatus::kOk: return "ok";
    case WheelStatus::kLowSpeed: return "low_speed";
    case WheelStatus::kNoInput: return "no_input";
    case WheelStatus::kStaleInput: return "stale_input";
    case WheelStatus::kInvalidInput: return "invalid_input";
    case WheelStatus::kTimeJump: return "time_jump";
  }
  return "unknown";
}

bool InputLimits::validate(std::string* error) const {
  if (!(max_load_n > 0.0) || !std::isfinite(max_load_n))
    return failValidation(error, "max_load_n", max_load_n, "finite and > 0");
  if (!(max_abs_slip_angle_rad > 0.0 && max_abs_slip_angle_rad < 0.5 * units::kPi))
    return failValidation(error, "max_abs_slip_angle_rad", max_abs_slip_angle_rad, "in (0, pi/2)");
  if (!(max_abs_slip_ratio > 0.0 && max_abs_slip_ratio <= 1.0))
    return failValidation(error, "max_abs_slip_ratio", max_abs_slip_ratio, "in (0, 1]");
  if (!(max_abs_path_curvature_per_m > 0.0) || !std::isfinite(max_abs_path_curvature_per_m))
    return failValidation(error, "max_abs_path_curvature_per_m", max_abs_path_curvature_per_m, "finite and > 0");
  if (!(max_speed_mps > 0.0) || !std::isfinite(max_speed_mps))
    return failValidation(error, "max_speed_mps", max_speed_mps, "finite and > 0");
  if (!std::isfinite(min_temperature_c)) return failValidation(error, "min_temperature_c", min_temperature_c, "finite");
  if (!(max_temperature_c > min_temperature_c) || !std::isfinite(max_temperature_c))
    return failValidation(error, "max_temperature_c", max_temperature_c, "finite and > min_temperature_c");
  return true;
}

InputFault InputLimits::checkLoad(double load_n) const {
  if (!std::isfinite(load_n)) return InputFault::kNotFinite;
  if (load_n < 0.0) return InputFault::kNegativeLoad;
  if (load_n > max_load_n) return InputFault::kLoadTooLarge;
  return InputFault::kNone;
}

InputFault InputLimits::checkSlip(double slip_angle_rad, double slip_ratio, double path_curvature_per_m) const {
  if (!std::isfinite(slip_angle_rad) || !std::isfinite(slip_ratio) || !std::isfinite(path_curvature_per_m))
    return InputFault::kNotFinite;
  if (std::fabs(slip_angle_rad) > max_abs_slip_angle_rad) return InputFault::kSlipAngleOutOfRange;
  // kappa = -1 is a locked wheel (no rolling): outside the brush model's domain, like any |kappa| > max.
  if (std::fabs(slip_ratio) > max_abs_slip_ratio || slip_ratio <= -1.0) return InputFault::kSlipRatioOutOfRange;
  if (std::fabs(path_curvature_per_m) > max_abs_path_curvature_per_m) return InputFault::kCurvatureOutOfRange;
  return InputFault::kNone;
}

InputFault InputLimits::checkSpeed(double speed_mps) const {
  if (!std::isfinite(speed_mps)) return InputFault::kNotFinite;
  if (speed_mps < 0.0) return InputFault::kNegativeSpeed;
  if (speed_mps > max_speed_mps) return InputFault::kSpeedTooLarge;
  return InputFault::kNone;
}

InputFault InputLimits::checkTemperature(double temperature_c) const {
  if (!std::isfinite(temperature_c)) return InputFault::kNotFinite;
  if (temperature_c < min_temperature_c || temperature_c > max_temperature_c)
    return InputFault::kTemperatureOutOfRange;
  return InputFault::kNone;
}

InputFault WheelInputs::record(InputKind kind, double t_s, InputFault fault) {
  Sample& s = samples_[static_cast<int>(kind)];
  ++s.received;
  s.received_s = t_s;
  if (fault != InputFault::kNone) {
    ++s.rejected;
    ++fault_counts_[static_cast<int>(fault)];
    s.last_fault = fault;
    s.valid = false;
  } else {
    s.valid = true;
    s.stamp_s = t_s;
  }
  return fault;
}

InputFault WheelInputs::setLoad(double t_s, double load_n) {
  const InputFault fault = limits_.checkLoad(load_n);
  if (fault == InputFault::kNone) load_n_ = load_n;
  return record(InputKind::kLoad, t_s, fault);
}

InputFault WheelInputs::setSlip(double t_s, double slip_angle_rad, double slip_ratio, double path_curvature_per_m) {
  const InputFault fault = limits_.checkSlip(slip_angle_rad, slip_ratio, path_curvature_per_m);
  if (fault == InputFault::kNone) {
    slip_angle_rad_ = slip_angle_rad;
    slip_ratio_ = slip_ratio;
    curvature_ = path_curvature_per_m;
  }
  return record(InputKind::kSlip, t_s, fault);
}

InputFault WheelInputs::setSpeed(double t_s, double speed_mps) {
  const InputFault fault = limits_.checkSpeed(speed_mps);
  if (fault == InputFault::kNone) speed_mps_ = speed_mps;
  return record(InputKind::kSpeed, t_s, fault);
}

InputFault WheelInputs::setTemperature(double t_s, double temperature_c) {
  const InputFault fault = limits_.checkTemperature(temperature_c);
  if (fault == InputFault::kNone) temperature_c_ = temperature_c;
  return record(InputKind::kTemperature, t_s, fault);
}

InputFault WheelInputs::apply(const InputSample& s) {
  switch (s.kind) {
    case InputKind::kLoad: return setLoad(s.t_s, s.value[0]);
    case InputKind::kSlip: return setSlip(s.t_s, s.value[0], s.value[1], s.value[2]);
    case InputKind::kSpeed: return setSpeed(s.t_s, s.value[0]);
    case InputKind::kTemperature: return setTemperature(s.t_s, s.value[0]);
  }
  return InputFault::kNone;
}

std::uint64_t WheelInputs::totalRejected() const {
  std::uint64_t n = 0;
  for (const Sample& s : samples_) n += s.rejected;
  return n;
}

bool WheelEstimatorParams::validate(std::string* error) const {
  std::string limits_error;
  if (!limits.validate(&limits_error)) {
    if (error != nullptr) *error = "limits." + limits_error;
    return false;
  }
  if (!(stale_timeout_s > 0.0) || !std::isfinite(stale_timeout_s))
    return failValidation(error, "stale_timeout_s", stale_timeout_s, "finite and > 0");
  if (!(max_step_s > stale_timeout_s) || !std::isfinite(max_step_s))
    return failValidation(error, "max_step_s", max_step_s, "finite and > stale_timeout_s");
  return true;
}

WheelEstimator::WheelEstimator(const WheelEstimatorParams& params, const MaterialParams& material)
    : params_(params), material_(material) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid wheel estimator parameters: " + error);
  if (!material.validate(&error)) throw std::invalid_argument("invalid material parameters: " + error);
  mass_per_depth_kg_per_m_ = material_.massPerDepth_kg_per_m();
  updateDepth();
}

void WheelEstimator::restore(const WheelAccumulators& accumulators) {
  output_.accumulated_loss_kg = accumulators.accumulated_loss_kg;
  output_.distance_m = accumulators.distance_m;
  prev_evaluated_ = false;
  prev_cause_ = WheelStatus::kNoInput;
  updateDepth();
}

void WheelEstimator::updateDepth() {
  output_.tread_depth_loss_m = output_.accumulated_loss_kg / mass_per_depth_kg_per_m_;
  const double remaining = material_.tread_depth_m - output_.tread_depth_loss_m;
  output_.remaining_tread_depth_m = remaining > 0.0 ? remaining : 0.0;
}

void WheelEstimator::loseInterval(double dt, WheelStatus cause) {
  if (!(dt > 0.0)) return;  // a backward jump has no length to lose
  unaccounted_s_ += dt;
  unaccounted_by_cause_s_[static_cast<int>(cause)] += dt;
}

WheelStatus requiredInputStatus(const WheelInputs& inputs, double now_s, double stale_timeout_s) {
  WheelStatus status = WheelStatus::kOk;
  for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed}) {
    const WheelInputs::Sample& s = inputs.sample(kind);
    WheelStatus st = WheelStatus::kOk;
    if (s.received == 0) {
      st = WheelStatus::kNoInput;
    } else if (!s.valid) {
      st = WheelStatus::kInvalidInput;
    } else if (std::fabs(now_s - s.stamp_s) > stale_timeout_s) {
      st = WheelStatus::kStaleInput;
    }
    // Report the most actionable problem: invalid data over stale data over missing data.
    if (st == WheelStatus::kInvalidInput || (st == WheelStatus::kStaleInput && status != WheelStatus::kInvalidInput) ||
        (st == WheelStatus::kNoInput && status == WheelStatus::kOk))
      status = st;
  }
  return status;
}

const WheelOutput& WheelEstimator::step(double now_s, const WheelInputs& inputs, const WearModel& model,
                                        PatchFields* fields) {
  output_.evaluated = false;
  output_.integrated = false;

  // Clock: a backward step or an implausibly long forward step is a jump; restart the interval there.
  double dt = 0.0;
  bool jumped = false;
  if (have_time_) {
    dt = now_s - last_time_s_;
    if (dt < 0.0) {
      ++backward_jumps_;
      jumped = true;
    } else if (dt > params_.max_step_s) {
      ++forward_jumps_;
      jumped = true;
    }
  }
  have_time_ = true;
  last_time_s_ = now_s;

  // Sample the required inputs: each must exist, be valid and be fresh. An input stamped in the future (possible
  // just after the clock jumped backwards) counts as stale.
  const WheelStatus input_status = requiredInputStatus(inputs, now_s, params_.stale_timeout_s);
  if (input_status == WheelStatus::kStaleInput) ++stale_steps_;

  if (input_status != WheelStatus::kOk) {
    output_.status = jumped ? WheelStatus::kTimeJump : input_status;
    loseInterval(dt, output_.status);
    prev_evaluated_ = false;
    prev_cause_ = input_status;
    return output_;
  }

  // Evaluate (a zero load, wheel off the ground, carries no force and wears nothing: evaluateInputs).
  const double speed = inputs.speed_mps();
  const EvalStatus es = evaluateInputs(model, inputs, now_s, params_.stale_timeout_s, &output_.result, fields);
  if (es == EvalStatus::kInvalidInput) {
    // Unreachable with validated inputs unless limits exceed the model's domain; never integrate it.
    loseInterval(dt, jumped ? WheelStatus::kTimeJump : WheelStatus::kInvalidInput);
    prev_evaluated_ = false;
    prev_cause_ = WheelStatus::kInvalidInput;
    output_.status = WheelStatus::kInvalidInput;
    return output_;
  }
  const WheelStatus eval_status = es == EvalStatus::kLowSpeed ? WheelStatus::kLowSpeed : WheelStatus::kOk;
  const double wear_kg_per_s = output_.result.wear_rate_kg_per_s;
  ++evaluations_;
  output_.evaluated = true;
  output_.preset = model.activePreset();

  if (jumped) {
    output_.status = WheelStatus::kTimeJump;
  } else {
    output_.status = eval_status;
    if (prev_evaluated_) {
      output_.accumulated_loss_kg += 0.5 * (prev_wear_kg_per_s_ + wear_kg_per_s) * dt;
      output_.distance_m += 0.5 * (prev_speed_mps_ + speed) * dt;
      output_.integrated = true;
      integrated_s_ += dt;
      updateDepth();
    }
  }
  if (!output_.integrated) loseInterval(dt, jumped ? WheelStatus::kTimeJump : prev_cause_);
  prev_evaluated_ = true;
  prev_wear_kg_per_s_ = wear_kg_per_s;
  prev_speed_mps_ = speed;
  return output_;
}

OperatingPoint operatingPoint(const WheelInputs& inputs, double now_s, double stale_timeout_s) {
  OperatingPoint op;
  op.speed_mps = inputs.speed_mps();
  op.slip_angle_rad = inputs.slipAngle_rad();
  op.slip_ratio = inputs.slipRatio();
  op.path_curvature_per_m = inputs.pathCurvature_per_m();
  op.load_n = inputs.load_n();
  const WheelInputs::Sample& temperature = inputs.sample(InputKind::kTemperature);
  const bool fresh = temperature.valid && std::fabs(now_s - temperature.stamp_s) <= stale_timeout_s;
  op.tread_temperature_c = fresh ? inputs.temperature_c() : std::numeric_limits<double>::quiet_NaN();
  return op;
}

EvalStatus evaluateInputs(const WearModel& model, const WheelInputs& inputs, double now_s, double stale_timeout_s,
                          WearResult* result, PatchFields* fields) {
  if (!(inputs.load_n() > 0.0)) {
    *result = WearResult();
    if (fields != nullptr) fields->resize(0, 0);  // no patch; shrinking keeps the capacity (no allocation)
    return EvalStatus::kOk;
  }
  return model.evaluate(operatingPoint(inputs, now_s, stale_timeout_s), result, fields);
}

}  // namespace tread_wear
