#pragma once
/// @file rolling_radius_learner.h
/// Online learning of each wheel's effective rolling radius R_e against an independent ground-speed reference
/// (GNSS or a vehicle speed that does not come from these wheels), on free-rolling straights.
///
/// Observation: a wheel rolling at angular speed omega with slip ratio kappa over ground speed V_x (along its
/// heading) has omega R_e = V_x (1 + kappa) (operating_point.h: kappa = (V_r - V_x)/V_x, V_r = omega R_e), so
///   R_obs = V_x (1 + kappa_prior) / omega
/// with kappa_prior the quasi-steady slip of the wheel's force demand (small on a free-rolling straight: rolling
/// resistance and drag, ~1e-3; its error goes one to one into the radius).
/// Accepted only on a free-rolling straight: V_x >= min_speed, |a_x| <= max_long_accel, |r| <= max_yaw_rate,
/// |delta| <= max_steer, |kappa_prior| <= max_slip_prior, and R_obs within max_relative_deviation of the nominal.
/// Update, distance-weighted mean that turns into exponential forgetting over averaging_distance_m:
///   R += ds / (min(D, D_avg) + ds) (R_obs - R),  D += ds   (D: distance learned so far [m])
/// so the first kilometre is a plain mean (no pull towards the nominal) and later changes (wear, pressure) are
/// followed over D_avg. Converged once D >= converged_distance_m.
/// Persistence: state() / restore() carry (R_e, D) per wheel, so a restart continues where it stopped.
/// Real time: no allocation; not thread-safe.

#include <array>
#include <string>

#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

struct RollingRadiusLearnerParams {
  double min_speed_mps = 8.0;           ///< slowest ground speed to learn at [m/s], > 0
  double max_long_accel_mps2 = 0.3;     ///< largest |a_x| of a free-rolling straight [m/s^2], > 0
  double max_yaw_rate_rps = 0.01;       ///< largest |r| of a straight [rad/s], > 0
  double max_steer_rad = 0.01;          ///< largest |road-wheel steer angle| of a straight [rad], > 0
  double max_slip_prior = 0.003;        ///< largest |kappa_prior| of a free-rolling wheel [-], > 0
  double averaging_distance_m = 500.0;  ///< D_avg, forgetting distance [m], > 0
  double converged_distance_m = 1000.0; ///< distance learned before the radius counts as converged [m], >= 0
  double max_relative_deviation = 0.05; ///< |R_obs/R_nominal - 1| above this is rejected [-], in (0, 0.5]

  bool validate(std::string* error) const;
};

/// Learned state of one wheel (what a state file persists).
struct RollingRadiusState {
  double radius_m = 0.0;           ///< effective rolling radius R_e [m], > 0
  double learned_distance_m = 0.0; ///< distance over which it was learned [m], >= 0
};

class RollingRadiusLearner {
 public:
  /// @param nominal_radius_m starting (and reference) radius of each wheel [m], > 0
  /// @throw std::invalid_argument naming the field for invalid params or radii
  RollingRadiusLearner(const RollingRadiusLearnerParams& params, const std::array<double, kWheelCount>& nominal_radius_m);

  /// Offers one observation of wheel `wheel` over distance ds_m [m] (> 0). Returns true when it was used.
  bool addObservation(int wheel, double ds_m, double omega_rps, double ground_speed_mps, double long_accel_mps2,
                      double yaw_rate_rps, double steer_rad, double slip_prior);

  double radius(int wheel) const { return state_[static_cast<std::size_t>(wheel)].radius_m; }
  bool converged(int wheel) const;
  const std::array<RollingRadiusState, kWheelCount>& state() const { return state_; }
  /// Restores persisted state; false (and nothing changed) when a radius is not finite and > 0 or a distance < 0.
  bool restore(const std::array<RollingRadiusState, kWheelCount>& state);
  const RollingRadiusLearnerParams& params() const { return params_; }

 private:
  RollingRadiusLearnerParams params_;
  std::array<double, kWheelCount> nominal_;
  std::array<RollingRadiusState, kWheelCount> state_;
};

}  // namespace tread_wear
