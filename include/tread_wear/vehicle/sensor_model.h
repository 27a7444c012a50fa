#pragma once
/// @file sensor_model.h
/// What a car's own sensors would have measured on a drive of the quasi-steady vehicle model (vehicle_model.h):
/// the inverse problem's test data (docs/vehicle_inputs.md, "Proof on known truth"). ROS-free; the drive
/// generator writes the readings as sensor messages (ros/bag/drive_bag_writer.h).
///
/// Truth: the VehicleState of VehicleModel::evaluate at the sample time (flat road, body frame = ISO 8855 at the
/// CoG; base_link is the CoG). Sensors:
///   IMU      specific force of the CoG path in body axes f_b = (a_x cos b - a_y sin b, a_x sin b + a_y cos b, g)
///            (b sideslip, a_y = v^2 kappa), angular rate w_b = (0, 0, v kappa); in IMU axes through the mount
///            rotation R_m = Rz(yaw) Ry(pitch) Rx(roll) (IMU -> body): f_imu = R_m^T f_b + b_a + n_a,
///            w_imu = R_m^T w_b + b_g + n_g; white noise per sample sigma = density sqrt(rate) (n ~ N(0, sigma^2)).
///            At the IMU position p (from the CoG, body axes) the rigid body adds r_dot x p + r x (r x p) to f_b
///            (r = (0, 0, v kappa), r_dot its time derivative, given by the caller).
///   wheels   omega_i = V_i cos(alpha_i) (1 + kappa_i) / R_true,i + jitter, quantised to the signal resolution
///            (round to a multiple of the quantum), >= 0; R_true,i = R_nominal (1 + radius_error_i): the nominal
///            radius is what the car's documentation (and the front end) assumes.
///   steering steering-wheel angle = i_s delta (delta: mean front road-wheel angle of the truth, i_s the steering
///            ratio), quantised.
///   speed    odometry speed |v| + noise, measured at its stamp and delivered odometry_lag_s later.
/// Every sensor has its own random stream (seed + sensor index), so adding samples of one leaves the others'
/// noise unchanged.

#include <array>
#include <cstdint>
#include <random>
#include <string>

#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

struct SensorModelParams {
  // IMU
  std::array<double, 3> imu_mount_rpy_rad{{0.017453292519943295, 0.03490658503988659, 0.05235987755982989}};
  ///< mount rotation IMU -> body: roll 1 deg, pitch 2 deg, yaw 3 deg [rad]
  std::array<double, 3> imu_position_m{{0.3, 0.1, -0.2}};
  ///< IMU origin from the CoG in body axes (centre console: ahead, left of and below the CoG) [m]
  double imu_rate_hz = 100.0;                                    ///< [Hz], > 0
  std::array<double, 3> accel_bias_mps2{{0.03, -0.02, 0.05}};    ///< accelerometer bias, IMU axes [m/s^2]
  std::array<double, 3> gyro_bias_rps{{0.002, -0.001, 0.003}};   ///< gyro bias, IMU axes [rad/s]
  double accel_noise_density = 0.003;   ///< white noise [m/s^2/sqrt(Hz)] (0.03 m/s^2 per sample at 100 Hz), >= 0
  double gyro_noise_density = 1e-4;     ///< white noise [rad/s/sqrt(Hz)] (1 mrad/s per sample at 100 Hz), >= 0

  // wheel speeds and steering (one joint_states message)
  double wheel_rate_hz = 100.0;                 ///< [Hz], > 0
  double wheel_radius_nominal_m = 0.305;        ///< R_nominal, the radius the front end is told [m], > 0
  std::array<double, kWheelCount> wheel_radius_error{{0.01, 0.01, 0.01, 0.01}};
  ///< R_true = R_nominal (1 + error) per wheel FL, FR, RL, RR [-], > -0.5
  double wheel_speed_quantum_rps = 0.02;        ///< wheel-speed signal resolution [rad/s], >= 0 (0: none)
  double wheel_speed_noise_rps = 0.005;         ///< jitter before quantisation [rad/s], >= 0
  double steering_ratio = 15.0;                 ///< i_s, steering-wheel per road-wheel angle [-], > 0
  double steering_quantum_rad = 0.0017453292519943296;  ///< steering-wheel angle resolution (0.1 deg) [rad], >= 0

  // odometry
  double odometry_rate_hz = 10.0;               ///< [Hz], > 0
  double odometry_lag_s = 0.1;                  ///< delivery delay after the measurement [s], >= 0
  double odometry_noise_mps = 0.02;             ///< white noise per sample [m/s], >= 0

  std::uint32_t seed = 20240601;                ///< random streams (fixed: a drive is reproducible)

  /// Names field, value and broken constraint of the first invalid parameter.
  bool validate(std::string* error) const;
};

struct ImuReading {
  std::array<double, 3> specific_force_mps2{};  ///< IMU axes [m/s^2]
  std::array<double, 3> angular_rate_rps{};     ///< IMU axes [rad/s]
};

class SensorModel {
 public:
  /// @throw std::invalid_argument naming the field for invalid params
  SensorModel(const SensorModelParams& params, double gravity_mps2);

  /// IMU sample for the vehicle's motion, its evaluated state and its yaw acceleration [rad/s^2].
  ImuReading imu(const VehicleMotion& motion, const VehicleState& state, double yaw_accel_rps2);
  /// Wheel angular speeds [rad/s], FL, FR, RL, RR.
  std::array<double, kWheelCount> wheelSpeeds(const VehicleState& state);
  /// Steering-wheel angle [rad], > 0 left.
  double steeringWheelAngle(const VehicleState& state) const;
  /// Odometry speed [m/s] at the measurement time (delivered odometry_lag_s later).
  double odometrySpeed(const VehicleMotion& motion);

  /// True rolling radius of a wheel [m].
  double trueRadius(int wheel) const;
  const SensorModelParams& params() const { return params_; }

  /// Row-major R_m = Rz(yaw) Ry(pitch) Rx(roll) of rpy (IMU -> body).
  static std::array<double, 9> mountRotation(const std::array<double, 3>& rpy);
  /// Unit quaternion (x, y, z, w) of the rotation rpy, as tf's setRPY.
  static std::array<double, 4> quaternion(const std::array<double, 3>& rpy);
  /// Roll, pitch, yaw of a quaternion (x, y, z, w) (inverse of quaternion()).
  static std::array<double, 3> rpyOf(const std::array<double, 4>& q);

 private:
  SensorModelParams params_;
  double gravity_mps2_;
  std::array<double, 9> mount_{};
  std::mt19937_64 imu_rng_, wheel_rng_, odometry_rng_;
  std::normal_distribution<double> imu_normal_{0.0, 1.0}, wheel_normal_{0.0, 1.0}, odometry_normal_{0.0, 1.0};
};

}  // namespace tread_wear
