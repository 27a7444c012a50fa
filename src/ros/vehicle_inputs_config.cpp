#include "tread_wear/ros/vehicle_inputs_config.h"

#include <cmath>
#include <set>
#include <sstream>
#include <vector>

#include "tread_wear/io/vehicle_params_io.h"

namespace tread_wear {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Reads pnh/key into *value when present; false with *error when present with the wrong type.
bool read(const ros::NodeHandle& pnh, const std::string& key, double* value, std::string* error) {
  if (!pnh.hasParam(key)) return true;
  if (pnh.getParam(key, *value)) return true;
  int i = 0;
  if (pnh.getParam(key, i)) {
    *value = i;
    return true;
  }
  *error = key + ": must be a number";
  return false;
}

bool read(const ros::NodeHandle& pnh, const std::string& key, std::string* value, std::string* error) {
  if (!pnh.hasParam(key) || pnh.getParam(key, *value)) return true;
  *error = key + ": must be a string";
  return false;
}

template <std::size_t N>
bool read(const ros::NodeHandle& pnh, const std::string& key, std::array<double, N>* value, std::string* error) {
  if (!pnh.hasParam(key)) return true;
  std::vector<double> v;
  if (!pnh.getParam(key, v) || v.size() != N) {
    *error = key + ": must be a list of " + std::to_string(N) + " numbers";
    return false;
  }
  for (std::size_t i = 0; i < N; ++i) (*value)[i] = v[i];
  return true;
}

template <std::size_t N>
bool read(const ros::NodeHandle& pnh, const std::string& key, std::array<std::string, N>* value, std::string* error) {
  if (!pnh.hasParam(key)) return true;
  std::vector<std::string> v;
  if (!pnh.getParam(key, v) || v.size() != N) {
    *error = key + ": must be a list of " + std::to_string(N) + " strings (FL, FR, RL, RR)";
    return false;
  }
  for (std::size_t i = 0; i < N; ++i) (*value)[i] = v[i];
  return true;
}

template <std::size_t N>
bool uniqueNonEmpty(const std::array<std::string, N>& names, const std::string& key, std::string* error) {
  std::set<std::string> seen;
  for (const std::string& n : names) {
    if (n.empty() || !seen.insert(n).second) {
      *error = key + " = '" + n + "': must be non-empty and unique";
      return false;
    }
  }
  return true;
}

}  // namespace

bool VehicleInputsConfig::validate(std::string* error) const {
  if (!(publish_rate_hz > 0.0 && publish_rate_hz <= 1000.0)) {
    *error = "publish_rate_hz = " + number(publish_rate_hz) + ": must be in (0, 1000] [Hz]";
    return false;
  }
  if (speed_source != "odom" && speed_source != "twist") {
    *error = "speed_source = '" + speed_source + "': must be odom or twist";
    return false;
  }
  if (base_frame.empty()) {
    *error = "base_frame: must not be empty";
    return false;
  }
  for (double c : cog_position_m)
    if (!std::isfinite(c)) {
      *error = "cog_position_m: must be finite [m]";
      return false;
    }
  if (!uniqueNonEmpty(wheel_names, "wheel_names", error)) return false;
  if (!uniqueNonEmpty(wheel_joints, "wheel_joints", error)) return false;
  if (!uniqueNonEmpty(wheel_frames, "wheel_frames", error)) return false;
  for (double sign : wheel_velocity_signs)
    if (sign != 1.0 && sign != -1.0) {
      *error = "wheel_velocity_signs: " + number(sign) + ": each must be 1 or -1";
      return false;
    }
  if (steering_joint.empty()) {
    *error = "steering_joint: must not be empty";
    return false;
  }
  for (const std::string& j : wheel_joints)
    if (j == steering_joint) {
      *error = "steering_joint = '" + steering_joint + "': must differ from the wheel joints";
      return false;
    }
  if (!(tf_timeout_s >= 0.0 && tf_timeout_s <= 1.0)) {
    *error = "tf_timeout_s = " + number(tf_timeout_s) + ": must be in [0, 1] [s]";
    return false;
  }
  if (!(save_interval_s > 0.0)) {
    *error = "save_interval_s = " + number(save_interval_s) + ": must be > 0 [s]";
    return false;
  }
  if (!(diagnostic_period_s > 0.0)) {
    *error = "diagnostic_period_s = " + number(diagnostic_period_s) + ": must be > 0 [s]";
    return false;
  }
  if (!(marker_rate_hz >= 0.0 && marker_rate_hz <= publish_rate_hz)) {
    *error = "marker_rate_hz = " + number(marker_rate_hz) + ": must be in [0, publish_rate_hz] [Hz]";
    return false;
  }
  std::string estimator_error;
  if (!estimator.validate(&estimator_error)) {
    *error = "estimator: " + estimator_error;
    return false;
  }
  return true;
}

std::string VehicleInputsConfig::describe() const {
  std::ostringstream s;
  s << "publish_rate_hz: " << publish_rate_hz << "\nspeed_source: " << speed_source << "\nbase_frame: " << base_frame
    << "\ncog_position_m: [" << cog_position_m[0] << ", " << cog_position_m[1] << ", " << cog_position_m[2] << "]";
  for (int i = 0; i < kWheelCount; ++i)
    s << "\nwheel " << wheel_names[i] << ": joint " << wheel_joints[i] << " (sign " << wheel_velocity_signs[i]
      << "), frame " << wheel_frames[i];
  s << "\nsteering_joint: " << steering_joint << "\ntf_timeout_s: " << tf_timeout_s
    << "\nvehicle_params_file: " << vehicle_params_file << " (" << estimator.vehicle.name << ")"
    << "\nradius_file: " << (radius_file.empty() ? "(none)" : radius_file) << "\nsave_interval_s: " << save_interval_s
    << "\nmarker_rate_hz: " << marker_rate_hz;
  const VehicleInputEstimatorParams& e = estimator;
  s << "\nestimator/steering_ratio: " << e.steering_ratio << "\nestimator/steering_offset_rad: "
    << e.steering_offset_rad << "\nestimator/ackermann_share: " << e.ackermann_share << "\nestimator/wheel_radius_m: ["
    << e.wheel_radius_m[0] << ", " << e.wheel_radius_m[1] << ", " << e.wheel_radius_m[2] << ", " << e.wheel_radius_m[3]
    << "]\nestimator/speed_lag_s: " << e.speed_lag_s << "\nestimator/imu_timeout_s: " << e.imu_timeout_s
    << "\nestimator/wheel_timeout_s: " << e.wheel_timeout_s << "\nestimator/steering_timeout_s: "
    << e.steering_timeout_s << "\nestimator/speed_timeout_s: " << e.speed_timeout_s
    << "\nestimator/min_slip_speed_mps: " << e.min_slip_speed_mps;
  return s.str();
}

bool loadVehicleInputsConfig(const ros::NodeHandle& pnh, VehicleInputsConfig* config, std::string* error) {
  VehicleInputsConfig c;
  if (!read(pnh, "vehicle_params_file", &c.vehicle_params_file, error)) return false;
  if (c.vehicle_params_file.empty()) {
    *error = "vehicle_params_file: required (config/vehicle_*.yaml)";
    return false;
  }
  try {
    c.estimator.vehicle = loadVehicleParams(c.vehicle_params_file);
  } catch (const std::exception& e) {
    *error = std::string("vehicle_params_file: ") + e.what();
    return false;
  }
  c.cog_position_m = {0.0, 0.0, c.estimator.vehicle.cog_height_m};
  c.cog_position_set = pnh.hasParam("cog_position_m");
  VehicleInputEstimatorParams& e = c.estimator;
  const bool ok =
      read(pnh, "publish_rate_hz", &c.publish_rate_hz, error) && read(pnh, "speed_source", &c.speed_source, error) &&
      read(pnh, "base_frame", &c.base_frame, error) && read(pnh, "cog_position_m", &c.cog_position_m, error) &&
      read(pnh, "wheel_names", &c.wheel_names, error) && read(pnh, "wheel_joints", &c.wheel_joints, error) &&
      read(pnh, "wheel_frames", &c.wheel_frames, error) &&
      read(pnh, "wheel_velocity_signs", &c.wheel_velocity_signs, error) &&
      read(pnh, "steering_joint", &c.steering_joint, error) && read(pnh, "tf_timeout_s", &c.tf_timeout_s, error) &&
      read(pnh, "radius_file", &c.radius_file, error) && read(pnh, "save_interval_s", &c.save_interval_s, error) &&
      read(pnh, "diagnostic_period_s", &c.diagnostic_period_s, error) &&
      read(pnh, "marker_rate_hz", &c.marker_rate_hz, error) &&
      read(pnh, "estimator/accel_bias_mps2", &e.accel_bias_mps2, error) &&
      read(pnh, "estimator/gyro_bias_rps", &e.gyro_bias_rps, error) &&
      read(pnh, "estimator/gyro_bias_time_constant_s", &e.gyro_bias_time_constant_s, error) &&
      read(pnh, "estimator/load_filter_time_constant_s", &e.load_filter_time_constant_s, error) &&
      read(pnh, "estimator/lateral_complement_time_constant_s", &e.lateral_complement_time_constant_s, error) &&
      read(pnh, "estimator/steering_ratio", &e.steering_ratio, error) &&
      read(pnh, "estimator/steering_offset_rad", &e.steering_offset_rad, error) &&
      read(pnh, "estimator/ackermann_share", &e.ackermann_share, error) &&
      read(pnh, "estimator/wheel_radius_m", &e.wheel_radius_m, error) &&
      read(pnh, "estimator/wheel_speed_quantum_rps", &e.wheel_speed_quantum_rps, error) &&
      read(pnh, "estimator/speed_lag_s", &e.speed_lag_s, error) &&
      read(pnh, "estimator/speed_sigma_mps", &e.speed_sigma_mps, error) &&
      read(pnh, "estimator/imu_timeout_s", &e.imu_timeout_s, error) &&
      read(pnh, "estimator/wheel_timeout_s", &e.wheel_timeout_s, error) &&
      read(pnh, "estimator/steering_timeout_s", &e.steering_timeout_s, error) &&
      read(pnh, "estimator/speed_timeout_s", &e.speed_timeout_s, error) &&
      read(pnh, "estimator/min_slip_speed_mps", &e.min_slip_speed_mps, error) &&
      read(pnh, "estimator/standstill_speed_mps", &e.standstill_speed_mps, error) &&
      read(pnh, "estimator/max_step_s", &e.max_step_s, error) &&
      read(pnh, "estimator/max_dead_reckoning_s", &e.max_dead_reckoning_s, error);
  if (!ok || !c.validate(error)) return false;
  *config = c;
  return true;
}

}  // namespace tread_wear
