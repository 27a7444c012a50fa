#include "tread_wear/estimation/rolling_radius_learner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {
bool positive(double v) { return std::isfinite(v) && v > 0.0; }
}  // namespace

bool RollingRadiusLearnerParams::validate(std::string* error) const {
  if (!positive(min_speed_mps)) return failValidation(error, "min_speed_mps", min_speed_mps, "finite and > 0");
  if (!positive(max_long_accel_mps2))
    return failValidation(error, "max_long_accel_mps2", max_long_accel_mps2, "finite and > 0");
  if (!positive(max_yaw_rate_rps)) return failValidation(error, "max_yaw_rate_rps", max_yaw_rate_rps, "finite and > 0");
  if (!positive(max_steer_rad)) return failValidation(error, "max_steer_rad", max_steer_rad, "finite and > 0");
  if (!positive(max_slip_prior)) return failValidation(error, "max_slip_prior", max_slip_prior, "finite and > 0");
  if (!positive(averaging_distance_m))
    return failValidation(error, "averaging_distance_m", averaging_distance_m, "finite and > 0");
  if (!(std::isfinite(converged_distance_m) && converged_distance_m >= 0.0))
    return failValidation(error, "converged_distance_m", converged_distance_m, "finite and >= 0");
  if (!(positive(max_relative_deviation) && max_relative_deviation <= 0.5))
    return failValidation(error, "max_relative_deviation", max_relative_deviation, "in (0, 0.5]");
  return true;
}

RollingRadiusLearner::RollingRadiusLearner(const RollingRadiusLearnerParams& params,
                                           const std::array<double, kWheelCount>& nominal_radius_m)
    : params_(params), nominal_(nominal_radius_m) {
  std::string error;
  if (!params_.validate(&error)) throw std::invalid_argument("invalid rolling-radius learner parameters: " + error);
  for (int i = 0; i < kWheelCount; ++i) {
    const double r = nominal_[static_cast<std::size_t>(i)];
    if (!positive(r)) {
      failValidation(&error, std::string("wheel_radius_m[") + wheelName(i) + "]", r, "finite and > 0");
      throw std::invalid_argument("invalid rolling-radius learner parameters: " + error);
    }
    state_[static_cast<std::size_t>(i)] = {r, 0.0};
  }
}

bool RollingRadiusLearner::addObservation(int wheel, double ds_m, double omega_rps, double ground_speed_mps,
                                          double long_accel_mps2, double yaw_rate_rps, double steer_rad,
                                          double slip_prior) {
  if (wheel < 0 || wheel >= kWheelCount || !(ds_m > 0.0) || !std::isfinite(ds_m)) return false;
  const RollingRadiusLearnerParams& p = params_;
  if (!(ground_speed_mps >= p.min_speed_mps) || !(std::abs(long_accel_mps2) <= p.max_long_accel_mps2) ||
      !(std::abs(yaw_rate_rps) <= p.max_yaw_rate_rps) || !(std::abs(steer_rad) <= p.max_steer_rad) ||
      !(std::abs(slip_prior) <= p.max_slip_prior) || !(omega_rps > 0.0))
    return false;
  const auto w = static_cast<std::size_t>(wheel);
  const double observed = ground_speed_mps * (1.0 + slip_prior) / omega_rps;
  if (!(std::abs(observed / nominal_[w] - 1.0) <= p.max_relative_deviation)) return false;
  RollingRadiusState& s = state_[w];
  s.radius_m += ds_m / (std::min(s.learned_distance_m, p.averaging_distance_m) + ds_m) * (observed - s.radius_m);
  s.learned_distance_m += ds_m;
  return true;
}

bool RollingRadiusLearner::converged(int wheel) const {
  return state_[static_cast<std::size_t>(wheel)].learned_distance_m >= params_.converged_distance_m;
}

bool RollingRadiusLearner::restore(const std::array<RollingRadiusState, kWheelCount>& state) {
  for (const RollingRadiusState& s : state)
    if (!positive(s.radius_m) || !(std::isfinite(s.learned_distance_m) && s.learned_distance_m >= 0.0)) return false;
  state_ = state;
  return true;
}

}  // namespace tread_wear
