#pragma once
/// @file planar_velocity_observer.h
/// Kinematic planar velocity observer of the vehicle body: a linear time-varying Kalman filter (Eigen, fixed size)
/// over the CoG velocity in body axes and the two horizontal specific-force offsets. Used by
/// VehicleInputEstimator (vehicle_input_estimator.h), which supplies the inputs and the measurements.
///
/// State x = [v_x, v_y, b_x, b_y]^T:
///   v_x, v_y  CoG velocity in body axes (ISO 8855: x forward, y left) [m/s]
///   b_x, b_y  offset of the measured horizontal specific force from the kinematic acceleration [m/s^2]:
///             accelerometer bias left after calibration plus the gravity components of road grade and bank
///             (f_x = a_x + g sin(grade) + bias, f_y = a_y + g sin(bank) + bias); the two are not separable
///             without a map, so the estimator reports grade = asin(b_x/g), bank = asin(b_y/g).
/// Process (rigid body in the road plane, yaw rate r as a known input, zero-order hold over dt):
///   dv_x/dt = f_x - b_x + r v_y,   dv_y/dt = f_y - b_y - r v_x,   db/dt = w_b (random walk)
///   x_k+1 = F x_k + B u,  F = I + A dt,  Q = diag(s_a^2, s_a^2, s_b^2, s_b^2) dt
///   (s_a: specific-force noise incl. model error [m/s^2]; s_b: offset random walk [m/s^2/sqrt(s)]).
/// Measurements: scalar and linear, z = h^T x + offset + noise(variance), processed one at a time (Joseph form),
/// e.g. a wheel's ground speed along its heading, the reference speed, a single-track lateral velocity, or a
/// zero-velocity update at standstill.
/// Limits: planar (no heave, pitch or roll rates); first-order discretisation (dt well below 1/|r|).
/// Real time: no allocation; not thread-safe.

#include <Eigen/Core>
#include <string>

namespace tread_wear {

struct PlanarObserverParams {
  double accel_noise_mps2 = 0.5;            ///< s_a, specific-force input noise incl. model error [m/s^2], > 0
  double offset_random_walk_mps2_per_sqrt_s = 0.02;  ///< s_b, random walk of b_x, b_y [m/s^2/sqrt(s)], > 0
  double initial_velocity_sigma_mps = 2.0;  ///< prior standard deviation of v_x, v_y at a reset [m/s], > 0
  double initial_offset_sigma_mps2 = 0.5;   ///< prior standard deviation of b_x, b_y at a reset [m/s^2], > 0

  bool validate(std::string* error) const;
};

class PlanarVelocityObserver {
 public:
  using State = Eigen::Matrix<double, 4, 1>;
  using Covariance = Eigen::Matrix<double, 4, 4>;
  using Row = Eigen::Matrix<double, 4, 1>;
  enum Index { kVx = 0, kVy = 1, kBx = 2, kBy = 3 };

  /// @throw std::invalid_argument naming the field for invalid params
  explicit PlanarVelocityObserver(const PlanarObserverParams& params);

  /// Restarts at v_x, v_y [m/s] with offsets b_x, b_y [m/s^2] and the prior covariance.
  void reset(double v_x_mps, double v_y_mps, double b_x_mps2 = 0.0, double b_y_mps2 = 0.0);
  /// Propagates over dt_s [s] (> 0) with the body specific force f_x, f_y [m/s^2] and yaw rate r [rad/s].
  void predict(double dt_s, double f_x_mps2, double f_y_mps2, double yaw_rate_rps);
  /// Scalar update z = h^T x + offset with measurement variance > 0. Returns the normalised innovation squared;
  /// when it exceeds gate (> 0, infinity = no gate) the state is left unchanged and -1 is returned.
  double update(const Row& h, double offset, double z, double variance, double gate);

  const State& state() const { return x_; }
  const Covariance& covariance() const { return P_; }
  double sigma(Index i) const;  ///< standard deviation of state i (units of the state)

 private:
  PlanarObserverParams params_;
  State x_ = State::Zero();
  Covariance P_ = Covariance::Identity();
};

}  // namespace tread_wear
