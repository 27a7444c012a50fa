#pragma once
/// @file drive_motion.h
/// The motion of the car's centre of gravity over drive time, which a drive bag samples (ros/bag/drive_bag_writer.h):
/// speed v(t), longitudinal acceleration a_x(t) = dv/dt and the curvature kappa(s(t)) of the route at the distance
/// driven. Two kinds:
///   - ProfileMotion: a speed profile (a cycle such as the WLTC) driven as the cycle prescribes, over its route;
///   - SpeedTrace: a trace built from cells of constant acceleration (the manoeuvres of manoeuvre.h and the
///     envelope-limited drives of driving_style.h), optionally smoothed by a moving average over a window tau:
///         v_tau(t) = (s(t + tau/2) - s(t - tau/2)) / tau,   a_tau(t) = (v(t + tau/2) - v(t - tau/2)) / tau,
///         s_tau(t) = (1/tau) integral of s over [t - tau/2, t + tau/2].
///     The averages keep what the cells respect: a_tau lies between the smallest and largest cell acceleration in
///     the window, v_tau between the smallest and largest speed, and a stop of at least tau keeps v = 0 at its
///     position. They make the acceleration continuous, with jerk |da/dt| <= (max a - min a) / tau, so the
///     quasi-steady vehicle model never sees a step in a_x. The smoothed quantities are consistent: ds_tau/dt =
///     v_tau and dv_tau/dt = a_tau. Before its first cell the trace holds its start speed, after its last its end
///     speed.

#include <utility>
#include <vector>

#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

class DriveMotion {
 public:
  virtual ~DriveMotion() = default;
  /// Drive time of the first sample [s].
  virtual double startTime_s() const = 0;
  virtual double duration_s() const = 0;
  /// Distance from the start to the end of the drive [m].
  virtual double distance_m() const = 0;
  /// Motion at drive time t [s] (startTime_s() <= t <= startTime_s() + duration_s()).
  virtual VehicleMotion at(double t_s) const = 0;
  virtual const Route& route() const = 0;
};

/// The profile's speed and acceleration at t, the route's curvature at the profile's distance at t.
class ProfileMotion : public DriveMotion {
 public:
  ProfileMotion(SpeedProfile profile, Route route) : profile_(std::move(profile)), route_(std::move(route)) {}
  double startTime_s() const override { return profile_.startTime_s(); }
  double duration_s() const override { return profile_.duration_s(); }
  double distance_m() const override { return profile_.totalDistance_m(); }
  VehicleMotion at(double t_s) const override {
    return {profile_.speed(t_s), profile_.acceleration(t_s), route_.curvature(profile_.distance(t_s))};
  }
  const Route& route() const override { return route_; }

 private:
  SpeedProfile profile_;
  Route route_;
};

/// A stretch of constant acceleration [m/s^2] lasting duration_s [s] (> 0).
struct SpeedCell {
  double duration_s = 0.0;
  double accel_mps2 = 0.0;
};

class SpeedTrace : public DriveMotion {
 public:
  /// Starts at drive time 0 with start_speed_mps at distance 0 and runs through the cells; the drive lasts duration_s
  /// (the cells may run beyond it, so that the smoothing window at the end still sees them). smoothing_s = tau of
  /// the moving average (0: the cells as they are).
  /// @throw std::invalid_argument for a negative start speed or smoothing window, a duration <= 0, a cell with
  ///        duration <= 0, or cells that would drive the speed below zero
  SpeedTrace(double start_speed_mps, const std::vector<SpeedCell>& cells, double duration_s, double smoothing_s,
             Route route);

  double startTime_s() const override { return 0.0; }
  double duration_s() const override { return duration_s_; }
  double distance_m() const override { return distance_m_; }
  VehicleMotion at(double t_s) const override;
  const Route& route() const override { return route_; }
  double smoothing_s() const { return smoothing_s_; }
  /// Distance driven at t, the smoothed s_tau(t) (the cells' own without smoothing) [m].
  double position(double t_s) const;

 private:
  /// The cells' raw trace at t: speed, distance and the time integral of the distance, P = integral of s dt.
  struct Raw {
    double v, s, p;
  };
  Raw raw(double t_s) const;
  /// Cell start times, speeds, distances, integrals of distance, and the cells' accelerations.
  std::vector<double> t_, v_, s_, p_, a_;
  double duration_s_, smoothing_s_;
  Route route_;
  double distance_m_ = 0.0;  ///< (smoothed) distance at duration_s [m]
};

}  // namespace tread_wear
