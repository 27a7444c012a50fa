#pragma once
/// @file manoeuvre.h
/// Test manoeuvres for road-wear validation: drives at a known, steady operating condition, so that the wear of one
/// condition can be measured without the mix of a cycle (docs/drive.md, "Scenarios").
///   cruise:  constant speed V on a straight for T; a_x = a_y = 0, every wheel at its static load plus the
///            aerodynamic transfer F_aero h / L (vehicle_model.h). Starts at speed: no run-up is recorded.
///   circle:  steady cornering at V and lateral acceleration A on a circle of radius R = V^2 / A (constant
///            curvature +-1/R, left unless turning right) for T, entered at steady state: a_y = A from the first
///            sample, the lateral load transfer of vehicle_model.h.
///   accel:   on a straight, repeated cycles of accelerating at a from v_low to v_high and braking at d back to
///            v_low, from steady cruise at v_low at t = 0 (a_x = 0), for T. The cells' steps in acceleration are smoothed over
///            kAccelCycleSmoothing_s (drive_motion.h), so a_x moves between +a and -d with bounded jerk and never
///            beyond them; each phase holds its a_x for (v_high - v_low)/a - tau or (v_high - v_low)/d - tau.

#include <string>

#include "tread_wear/vehicle/drive_motion.h"

namespace tread_wear {

enum class Manoeuvre { kProfile = 0, kCruise = 1, kCircle = 2, kAccelCycles = 3 };
/// "profile", "cruise", "circle", "accel".
const char* manoeuvreName(Manoeuvre manoeuvre);
bool parseManoeuvre(const std::string& name, Manoeuvre* manoeuvre);

/// Sane bound of the manoeuvres' accelerations: 0.8 g, about the friction limit of a passenger-car tire on dry
/// asphalt (mu ~ 0.8-1.0). Beyond it the linear slip estimates of vehicle_model.h saturate [m/s^2].
constexpr double kMaxManoeuvreAccel_mps2 = 8.0;
/// Window of the accel cycles' smoothing, tau of drive_motion.h [s]: jerk <= (a + d) / tau.
constexpr double kAccelCycleSmoothing_s = 1.0;

/// One manoeuvre's settings. Only the fields of its kind are used (and validated).
struct ManoeuvreParams {
  Manoeuvre kind = Manoeuvre::kCruise;
  double speed_mps = 50.0 / 3.6;         ///< V of cruise and circle [m/s], > 0
  double lateral_accel_mps2 = 3.0;       ///< A of circle [m/s^2], in (0, kMaxManoeuvreAccel_mps2]
  bool turn_right = false;               ///< circle direction (false: left, curvature > 0)
  double duration_s = 60.0;              ///< T [s], > 0
  double low_speed_mps = 30.0 / 3.6;     ///< v_low of accel [m/s], >= 0
  double high_speed_mps = 80.0 / 3.6;    ///< v_high of accel [m/s], > v_low
  double accel_mps2 = 2.0;               ///< a of accel [m/s^2], in (0, kMaxManoeuvreAccel_mps2]
  double decel_mps2 = 3.0;               ///< d of accel, a positive number [m/s^2], in (0, kMaxManoeuvreAccel_mps2]

  /// False with "<field> = <value>: must be <constraint>" for the first bad field of the kind (not kProfile,
  /// which is the profile's drive and has no settings here).
  bool validate(std::string* error) const;
  /// Radius of the circle, V^2 / A [m].
  double circleRadius_m() const { return speed_mps * speed_mps / lateral_accel_mps2; }
};

/// The manoeuvre's drive: its route (a straight, or the circle) and speed trace.
/// @throw std::invalid_argument naming the field for invalid params or a kProfile kind
SpeedTrace buildManoeuvre(const ManoeuvreParams& params);

}  // namespace tread_wear
