#include "tread_wear/vehicle/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tread_wear {
namespace {

bool fail(std::string* error, const char* field, double value, const char* constraint) {
  if (error != nullptr) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "%s = %g: must be %s", field, value, constraint);
    *error = buffer;
  }
  return false;
}

double quantise(double value, double quantum) {
  return quantum > 0.0 ? std::round(value / quantum) * quantum : value;
}

}  // namespace

bool SensorModelParams::validate(std::string* error) const {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(imu_mount_rpy_rad[i]) || std::fabs(imu_mount_rpy_rad[i]) > 3.2)
      return fail(error, "imu_mount_rpy_rad", imu_mount_rpy_rad[i], "finite, |.| <= pi");
    if (!std::isfinite(accel_bias_mps2[i])) return fail(error, "accel_bias_mps2", accel_bias_mps2[i], "finite");
    if (!std::isfinite(gyro_bias_rps[i])) return fail(error, "gyro_bias_rps", gyro_bias_rps[i], "finite");
    if (!std::isfinite(imu_position_m[i]) || std::fabs(imu_position_m[i]) > 10.0)
      return fail(error, "imu_position_m", imu_position_m[i], "finite, |.| <= 10 m");
  }
  if (!(imu_rate_hz > 0.0) || !std::isfinite(imu_rate_hz)) return fail(error, "imu_rate_hz", imu_rate_hz, "> 0");
  if (!(accel_noise_density >= 0.0)) return fail(error, "accel_noise_density", accel_noise_density, ">= 0");
  if (!(gyro_noise_density >= 0.0)) return fail(error, "gyro_noise_density", gyro_noise_density, ">= 0");
  if (!(wheel_rate_hz > 0.0) || !std::isfinite(wheel_rate_hz))
    return fail(error, "wheel_rate_hz", wheel_rate_hz, "> 0");
  if (!(wheel_radius_nominal_m > 0.0) || !std::isfinite(wheel_radius_nominal_m))
    return fail(error, "wheel_radius_nominal_m", wheel_radius_nominal_m, "> 0");
  for (double e : wheel_radius_error)
    if (!(e > -0.5) || !std::isfinite(e)) return fail(error, "wheel_radius_error", e, "> -0.5");
  if (!(wheel_speed_quantum_rps >= 0.0)) return fail(error, "wheel_speed_quantum_rps", wheel_speed_quantum_rps, ">= 0");
  if (!(wheel_speed_noise_rps >= 0.0)) return fail(error, "wheel_speed_noise_rps", wheel_speed_noise_rps, ">= 0");
  if (!(steering_ratio > 0.0) || !std::isfinite(steering_ratio))
    return fail(error, "steering_ratio", steering_ratio, "> 0");
  if (!(steering_quantum_rad >= 0.0)) return fail(error, "steering_quantum_rad", steering_quantum_rad, ">= 0");
  if (!(odometry_rate_hz > 0.0) || !std::isfinite(odometry_rate_hz))
    return fail(error, "odometry_rate_hz", odometry_rate_hz, "> 0");
  if (!(odometry_lag_s >= 0.0) || !std::isfinite(odometry_lag_s))
    return fail(error, "odometry_lag_s", odometry_lag_s, ">= 0");
  if (!(odometry_noise_mps >= 0.0)) return fail(error, "odometry_noise_mps", odometry_noise_mps, ">= 0");
  return true;
}

SensorModel::SensorModel(const SensorModelParams& params, double gravity_mps2)
    : params_(params),
      gravity_mps2_(gravity_mps2),
      mount_(mountRotation(params.imu_mount_rpy_rad)),
      imu_rng_(static_cast<std::uint64_t>(params.seed) * 4 + 0),
      wheel_rng_(static_cast<std::uint64_t>(params.seed) * 4 + 1),
      odometry_rng_(static_cast<std::uint64_t>(params.seed) * 4 + 2) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("sensor model: " + error);
  if (!(gravity_mps2 > 0.0)) throw std::invalid_argument("sensor model: gravity must be > 0");
}

std::array<double, 9> SensorModel::mountRotation(const std::array<double, 3>& rpy) {
  const double cr = std::cos(rpy[0]), sr = std::sin(rpy[0]), cp = std::cos(rpy[1]), sp = std::sin(rpy[1]);
  const double cy = std::cos(rpy[2]), sy = std::sin(rpy[2]);
  return {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
          sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
          -sp,     cp * sr,                cp * cr};
}

std::array<double, 4> SensorModel::quaternion(const std::array<double, 3>& rpy) {
  const double hr = 0.5 * rpy[0], hp = 0.5 * rpy[1], hy = 0.5 * rpy[2];
  const double cr = std::cos(hr), sr = std::sin(hr), cp = std::cos(hp), sp = std::sin(hp);
  const double cy = std::cos(hy), sy = std::sin(hy);
  return {sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
          cr * cp * cy + sr * sp * sy};
}

std::array<double, 3> SensorModel::rpyOf(const std::array<double, 4>& q_in) {
  const double n = std::sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
  const double x = q_in[0] / n, y = q_in[1] / n, z = q_in[2] / n, w = q_in[3] / n;
  const double roll = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return {roll, pitch, yaw};
}

ImuReading SensorModel::imu(const VehicleMotion& motion, const VehicleState& state, double yaw_accel_rps2) {
  const double beta = state.sideslip_rad, a_x = motion.accel_mps2, a_y = state.lateral_accel_mps2;
  const double yaw = std::max(motion.speed_mps, 0.0) * motion.path_curvature_per_m;
  const std::array<double, 3>& p = params_.imu_position_m;
  // CoG specific force + r_dot x p + r x (r x p) for r = (0, 0, r).
  const std::array<double, 3> f_body = {
      a_x * std::cos(beta) - a_y * std::sin(beta) - yaw_accel_rps2 * p[1] - yaw * yaw * p[0],
      a_x * std::sin(beta) + a_y * std::cos(beta) + yaw_accel_rps2 * p[0] - yaw * yaw * p[1], gravity_mps2_};
  const std::array<double, 3> w_body = {0.0, 0.0, yaw};
  const double sigma_f = params_.accel_noise_density * std::sqrt(params_.imu_rate_hz);
  const double sigma_w = params_.gyro_noise_density * std::sqrt(params_.imu_rate_hz);
  ImuReading r;
  const std::array<double, 9>& R = mount_;
  for (int j = 0; j < 3; ++j) {  // R^T v: column j of R
    const double f = R[j] * f_body[0] + R[3 + j] * f_body[1] + R[6 + j] * f_body[2];
    const double w = R[j] * w_body[0] + R[3 + j] * w_body[1] + R[6 + j] * w_body[2];
    r.specific_force_mps2[j] = f + params_.accel_bias_mps2[j] + sigma_f * imu_normal_(imu_rng_);
    r.angular_rate_rps[j] = w + params_.gyro_bias_rps[j] + sigma_w * imu_normal_(imu_rng_);
  }
  return r;
}

std::array<double, kWheelCount> SensorModel::wheelSpeeds(const VehicleState& state) {
  std::array<double, kWheelCount> omega{};
  for (int i = 0; i < kWheelCount; ++i) {
    const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
    const double exact = w.speed_mps * std::cos(w.slip_angle_rad) * (1.0 + w.slip_ratio) / trueRadius(i);
    const double jitter = params_.wheel_speed_noise_rps * wheel_normal_(wheel_rng_);  // drawn always: fixed stream
    omega[static_cast<std::size_t>(i)] =
        exact > 0.0 ? std::max(0.0, quantise(exact + jitter, params_.wheel_speed_quantum_rps)) : 0.0;
  }
  return omega;
}

double SensorModel::steeringWheelAngle(const VehicleState& state) const {
  return quantise(params_.steering_ratio * state.steer_angle_rad, params_.steering_quantum_rad);
}

double SensorModel::odometrySpeed(const VehicleMotion& motion) {
  const double v = std::max(motion.speed_mps, 0.0);
  const double noise = params_.odometry_noise_mps * odometry_normal_(odometry_rng_);
  return v > 0.0 ? std::max(0.0, v + noise) : 0.0;
}

double SensorModel::trueRadius(int wheel) const {
  return params_.wheel_radius_nominal_m * (1.0 + params_.wheel_radius_error[static_cast<std::size_t>(wheel)]);
}

}  // namespace tread_wear
