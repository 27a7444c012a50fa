#include "tread_wear/io/vehicle_inputs_config.h"

#include <stdexcept>

#include "tread_wear/io/vehicle_params_io.h"

namespace tread_wear {
namespace {

/// The value at `key` of a map (nullptr when absent); "estimator/x" looks into the map `estimator`.
const ConfigValue* find(const ConfigValue& doc, const std::string& key) {
  const std::size_t slash = key.find('/');
  const auto it = doc.map.find(key.substr(0, slash));
  if (it == doc.map.end()) return nullptr;
  if (slash == std::string::npos) return &it->second;
  return it->second.type == ConfigValue::Type::kMap ? find(it->second, key.substr(slash + 1)) : nullptr;
}

bool wrongType(const std::string& key, const std::string& expected, std::string* error) {
  *error = key + ": must be " + expected;
  return false;
}

/// One value of the file's kind for T into *out; false (and *out untouched) for another kind.
bool take(const ConfigValue& v, double* out) {
  if (v.type != ConfigValue::Type::kNumber) return false;
  *out = v.number;
  return true;
}
bool take(const ConfigValue& v, bool* out) {
  if (v.type != ConfigValue::Type::kBool) return false;
  *out = v.boolean;
  return true;
}
bool take(const ConfigValue& v, std::string* out) {
  if (v.type != ConfigValue::Type::kString) return false;
  *out = v.string;
  return true;
}

/// What the error says a key of T (one value, or a list of N per wheel or per axis) must be.
const char* oneOf(const double*) { return "a number"; }
const char* oneOf(const bool*) { return "true or false"; }
const char* oneOf(const std::string*) { return "a string"; }
const char* listOf(const double*) { return "numbers"; }
const char* listOf(const std::string*) { return "strings (FL, FR, RL, RR)"; }

/// The value at `key` into *value; an absent key keeps the default.
template <class T>
bool read(const ConfigValue& doc, const std::string& key, T* value, std::string* error) {
  const ConfigValue* v = find(doc, key);
  if (v == nullptr || take(*v, value)) return true;
  return wrongType(key, oneOf(value), error);
}

/// A list of exactly N values at `key` into *value; an absent key keeps the default.
template <class T, std::size_t N>
bool read(const ConfigValue& doc, const std::string& key, std::array<T, N>* value, std::string* error) {
  const ConfigValue* v = find(doc, key);
  if (v == nullptr) return true;
  const std::string expected = "a list of " + std::to_string(N) + " " + listOf(value->data());
  if (v->type != ConfigValue::Type::kList || v->list.size() != N) return wrongType(key, expected, error);
  for (std::size_t i = 0; i < N; ++i)
    if (!take(v->list[i], &(*value)[i])) return wrongType(key, expected, error);
  return true;
}

bool readSpeedRule(const ConfigValue& doc, SpeedRule* rule, std::string* error) {
  std::string name = speedRuleName(*rule);
  if (!read(doc, "speed_rule", &name, error)) return false;
  if (parseSpeedRule(name, rule)) return true;
  *error = "speed_rule = '" + name + "': must be planar_norm or longitudinal";
  return false;
}

bool readEstimator(const ConfigValue& doc, VehicleInputEstimatorParams* e, std::string* error) {
  return read(doc, "estimator/accel_bias_mps2", &e->accel_bias_mps2, error) &&
         read(doc, "estimator/gyro_bias_rps", &e->gyro_bias_rps, error) &&
         read(doc, "estimator/gyro_bias_time_constant_s", &e->gyro_bias_time_constant_s, error) &&
         read(doc, "estimator/load_filter_time_constant_s", &e->load_filter_time_constant_s, error) &&
         read(doc, "estimator/lateral_complement_time_constant_s", &e->lateral_complement_time_constant_s, error) &&
         read(doc, "estimator/steering_ratio", &e->steering_ratio, error) &&
         read(doc, "estimator/steering_offset_rad", &e->steering_offset_rad, error) &&
         read(doc, "estimator/ackermann_share", &e->ackermann_share, error) &&
         read(doc, "estimator/wheel_radius_m", &e->wheel_radius_m, error) &&
         read(doc, "estimator/wheel_speed_quantum_rps", &e->wheel_speed_quantum_rps, error) &&
         read(doc, "estimator/speed_lag_s", &e->speed_lag_s, error) &&
         read(doc, "estimator/speed_sigma_mps", &e->speed_sigma_mps, error) &&
         read(doc, "estimator/imu_timeout_s", &e->imu_timeout_s, error) &&
         read(doc, "estimator/wheel_timeout_s", &e->wheel_timeout_s, error) &&
         read(doc, "estimator/steering_timeout_s", &e->steering_timeout_s, error) &&
         read(doc, "estimator/speed_timeout_s", &e->speed_timeout_s, error) &&
         read(doc, "estimator/min_slip_speed_mps", &e->min_slip_speed_mps, error) &&
         read(doc, "estimator/standstill_speed_mps", &e->standstill_speed_mps, error) &&
         read(doc, "estimator/max_step_s", &e->max_step_s, error) &&
         read(doc, "estimator/max_dead_reckoning_s", &e->max_dead_reckoning_s, error);
}

}  // namespace

bool readVehicleInputsConfig(const ConfigValue& doc, VehicleInputsConfig* config, std::string* error) {
  VehicleInputsConfig c;
  if (!read(doc, "vehicle_params_file", &c.vehicle_params_file, error)) return false;
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
  c.cog_position_set = find(doc, "cog_position_m") != nullptr;
  const bool ok =
      read(doc, "publish_rate_hz", &c.publish_rate_hz, error) && read(doc, "input_time", &c.input_time, error) &&
      read(doc, "speed_source", &c.speed_source, error) && readSpeedRule(doc, &c.speed_rule, error) &&
      read(doc, "input_delay_s", &c.input_delay_s, error) &&
      read(doc, "base_frame", &c.base_frame, error) && read(doc, "cog_position_m", &c.cog_position_m, error) &&
      read(doc, "wheel_names", &c.wheel_names, error) && read(doc, "wheel_joints", &c.wheel_joints, error) &&
      read(doc, "wheel_frames", &c.wheel_frames, error) &&
      read(doc, "wheel_velocity_signs", &c.wheel_velocity_signs, error) &&
      read(doc, "use_wheel_speeds", &c.use_wheel_speeds, error) &&
      read(doc, "steering_joint", &c.steering_joint, error) && read(doc, "tf_timeout_s", &c.tf_timeout_s, error) &&
      read(doc, "radius_file", &c.radius_file, error) && read(doc, "save_interval_s", &c.save_interval_s, error) &&
      read(doc, "diagnostic_period_s", &c.diagnostic_period_s, error) &&
      read(doc, "marker_rate_hz", &c.marker_rate_hz, error) && readEstimator(doc, &c.estimator, error);
  if (!ok || !c.validate(error)) return false;
  *config = c;
  return true;
}

VehicleInputsConfig loadVehicleInputsConfigFile(const std::string& path, const std::string& vehicle_params_file) {
  ConfigValue document = loadConfigDocument(path);
  if (document.type == ConfigValue::Type::kNull) document.type = ConfigValue::Type::kMap;
  if (document.type != ConfigValue::Type::kMap) throw std::runtime_error(path + ": not a map of keys");
  if (!vehicle_params_file.empty()) {
    ConfigValue file;
    file.type = ConfigValue::Type::kString;
    file.string = vehicle_params_file;
    document.map["vehicle_params_file"] = file;
  }
  VehicleInputsConfig config;
  std::string error;
  if (!readVehicleInputsConfig(document, &config, &error)) throw std::runtime_error(path + ": " + error);
  return config;
}

}  // namespace tread_wear
