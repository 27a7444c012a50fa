#include "tread_wear/ros/node_config.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include <set>
#include <sstream>

namespace tread_wear {
namespace {

bool fail(std::string* error, const std::string& key, const std::string& value, const std::string& constraint) {
  if (error != nullptr) *error = key + " = " + value + ": must be " + constraint;
  return false;
}

std::string str(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

bool readNumber(XmlRpc::XmlRpcValue& v, double* out) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    *out = static_cast<double>(v);
    return true;
  }
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    *out = static_cast<int>(v);
    return true;
  }
  return false;
}

bool readString(XmlRpc::XmlRpcValue& wheel, const char* key, std::string* out, bool required, std::string* error,
                const std::string& where) {
  if (!wheel.hasMember(key)) {
    if (required) return fail(error, where + "." + key, "(missing)", "given");
    return true;
  }
  if (wheel[key].getType() != XmlRpc::XmlRpcValue::TypeString)
    return fail(error, where + "." + key, wheel[key].toXml(), "a string");
  *out = static_cast<std::string>(wheel[key]);
  return true;
}

}  // namespace

bool NodeConfig::validate(std::string* error) const {
  if (!(update_rate_hz > 0.0 && update_rate_hz <= 1000.0))
    return fail(error, "update_rate_hz", str(update_rate_hz), "in (0, 1000]");
  if (!(marker_rate_hz >= 0.0 && marker_rate_hz <= update_rate_hz))
    return fail(error, "marker_rate_hz", str(marker_rate_hz), "in [0, update_rate_hz]");
  if (!(budget_us >= 0.0)) return fail(error, "budget_us", str(budget_us), ">= 0");
  if (!(min_speed_mps > 0.0)) return fail(error, "min_speed_mps", str(min_speed_mps), "> 0");
  if (!(save_interval_s > 0.0)) return fail(error, "save_interval_s", str(save_interval_s), "> 0");
  std::string sub;
  if (!estimator.validate(&sub)) {
    if (error != nullptr) *error = sub;
    return false;
  }
  if (wheels.empty()) return fail(error, "wheels", "[]", "a non-empty list");
  std::set<std::string> names;
  for (const WheelConfig& w : wheels) {
    if (w.name.empty()) return fail(error, "wheels[].name", "''", "non-empty");
    if (!names.insert(w.name).second) return fail(error, "wheels[].name", w.name, "unique");
    if (w.frame_id.empty()) return fail(error, "wheels[" + w.name + "].frame_id", "''", "non-empty");
    if (w.tire_params.empty()) return fail(error, "wheels[" + w.name + "].tire_params", "''", "a file path");
  }
  return true;
}

bool NodeConfig::load(const ros::NodeHandle& pnh, NodeConfig* c, std::string* error) {
  NodeConfig cfg;
  pnh.param("update_rate_hz", cfg.update_rate_hz, cfg.update_rate_hz);
  pnh.param("marker_rate_hz", cfg.marker_rate_hz, cfg.marker_rate_hz);
  pnh.param("budget_us", cfg.budget_us, cfg.budget_us);
  std::string preset = presetName(cfg.preset);
  pnh.param("preset", preset, preset);
  if (!parsePreset(preset, &cfg.preset)) return fail(error, "preset", preset, kPresetChoices);
  std::string orientation = orientationName(cfg.orientation);
  pnh.param("turn_slip_orientation", orientation, orientation);
  if (!parseOrientation(orientation, &cfg.orientation))
    return fail(error, "turn_slip_orientation", orientation, "literal or flipped");
  pnh.param("min_speed_mps", cfg.min_speed_mps, cfg.min_speed_mps);
  WheelEstimatorParams& e = cfg.estimator;
  pnh.param("stale_timeout_s", e.stale_timeout_s, e.stale_timeout_s);
  pnh.param("max_step_s", e.max_step_s, e.max_step_s);
  pnh.param("limits/max_load_n", e.limits.max_load_n, e.limits.max_load_n);
  pnh.param("limits/max_abs_slip_angle_rad", e.limits.max_abs_slip_angle_rad, e.limits.max_abs_slip_angle_rad);
  pnh.param("limits/max_abs_slip_ratio", e.limits.max_abs_slip_ratio, e.limits.max_abs_slip_ratio);
  pnh.param("limits/max_abs_path_curvature_per_m", e.limits.max_abs_path_curvature_per_m,
            e.limits.max_abs_path_curvature_per_m);
  pnh.param("limits/max_speed_mps", e.limits.max_speed_mps, e.limits.max_speed_mps);
  pnh.param("limits/min_temperature_c", e.limits.min_temperature_c, e.limits.min_temperature_c);
  pnh.param("limits/max_temperature_c", e.limits.max_temperature_c, e.limits.max_temperature_c);
  pnh.param("state_file", cfg.state_file, cfg.state_file);
  pnh.param("save_interval_s", cfg.save_interval_s, cfg.save_interval_s);
  pnh.param("base_frame", cfg.base_frame, cfg.base_frame);
  pnh.param("config_dir", cfg.config_dir, cfg.config_dir);

  XmlRpc::XmlRpcValue wheels;
  if (!pnh.getParam("wheels", wheels)) return fail(error, "wheels", "(missing)", "a list of wheels");
  if (wheels.getType() != XmlRpc::XmlRpcValue::TypeArray) return fail(error, "wheels", wheels.toXml(), "a list");
  for (int i = 0; i < wheels.size(); ++i) {
    XmlRpc::XmlRpcValue& w = wheels[i];
    const std::string where = "wheels[" + std::to_string(i) + "]";
    if (w.getType() != XmlRpc::XmlRpcValue::TypeStruct) return fail(error, where, w.toXml(), "a map");
    WheelConfig wc;
    if (!readString(w, "name", &wc.name, true, error, where)) return false;
    wc.frame_id = wc.name;
    wc.tire_id = "unknown";
    const std::string prefix = "wheels/" + wc.name + "/";
    wc.load_topic = prefix + "load";
    wc.slip_topic = prefix + "slip";
    wc.speed_topic = prefix + "speed";
    wc.temperature_topic = prefix + "tread_temperature";
    wc.wear_topic = prefix + "wear";
    if (!readString(w, "frame_id", &wc.frame_id, false, error, where) ||
        !readString(w, "tire_params", &wc.tire_params, true, error, where) ||
        !readString(w, "tire_id", &wc.tire_id, false, error, where) ||
        !readString(w, "load_topic", &wc.load_topic, false, error, where) ||
        !readString(w, "slip_topic", &wc.slip_topic, false, error, where) ||
        !readString(w, "speed_topic", &wc.speed_topic, false, error, where) ||
        !readString(w, "temperature_topic", &wc.temperature_topic, false, error, where) ||
        !readString(w, "wear_topic", &wc.wear_topic, false, error, where))
      return false;
    if (w.hasMember("position_m")) {
      XmlRpc::XmlRpcValue& p = w["position_m"];
      if (p.getType() != XmlRpc::XmlRpcValue::TypeArray || p.size() != 3)
        return fail(error, where + ".position_m", p.toXml(), "a list [x, y, z] in metres");
      for (int k = 0; k < 3; ++k)
        if (!readNumber(p[k], &wc.position_m[k]))
          return fail(error, where + ".position_m", p.toXml(), "three numbers [m]");
      wc.has_position = true;
    }
    if (!wc.tire_params.empty() && wc.tire_params[0] != '/' && !cfg.config_dir.empty())
      wc.tire_params = cfg.config_dir + "/" + wc.tire_params;
    cfg.wheels.push_back(wc);
  }
  if (!cfg.validate(error)) return false;
  *c = cfg;
  return true;
}

std::string NodeConfig::describe() const {
  std::ostringstream s;
  s.precision(10);
  s << "update_rate_hz: " << update_rate_hz << " [Hz]\n"
    << "marker_rate_hz: " << marker_rate_hz << " [Hz]\n"
    << "budget_us: " << budget_us << " [us] (0 = no budget)\n"
    << "preset: " << presetName(preset) << "\n"
    << "turn_slip_orientation: " << orientationName(orientation) << "\n"
    << "min_speed_mps: " << min_speed_mps << " [m/s]\n"
    << "stale_timeout_s: " << estimator.stale_timeout_s << " [s]\n"
    << "max_step_s: " << estimator.max_step_s << " [s]\n"
    << "limits/max_load_n: " << estimator.limits.max_load_n << " [N]\n"
    << "limits/max_abs_slip_angle_rad: " << estimator.limits.max_abs_slip_angle_rad << " [rad]\n"
    << "limits/max_abs_slip_ratio: " << estimator.limits.max_abs_slip_ratio << " [-]\n"
    << "limits/max_abs_path_curvature_per_m: " << estimator.limits.max_abs_path_curvature_per_m << " [1/m]\n"
    << "limits/max_speed_mps: " << estimator.limits.max_speed_mps << " [m/s]\n"
    << "limits/min_temperature_c: " << estimator.limits.min_temperature_c << " [degC]\n"
    << "limits/max_temperature_c: " << estimator.limits.max_temperature_c << " [degC]\n"
    << "state_file: " << (state_file.empty() ? "(none: persistence off)" : state_file) << "\n"
    << "save_interval_s: " << save_interval_s << " [s]\n"
    << "base_frame: " << base_frame << "\n"
    << "config_dir: " << config_dir << "\n";
  for (const WheelConfig& w : wheels) {
    s << "wheel " << w.name << ": frame_id " << w.frame_id << ", tire_params " << w.tire_params << ", tire_id "
      << w.tire_id << ", topics " << w.load_topic << " " << w.slip_topic << " " << w.speed_topic << " "
      << w.temperature_topic << " -> " << w.wear_topic;
    if (w.has_position)
      s << ", position_m [" << w.position_m[0] << ", " << w.position_m[1] << ", " << w.position_m[2] << "]";
    s << "\n";
  }
  return s.str();
}

}  // namespace tread_wear
