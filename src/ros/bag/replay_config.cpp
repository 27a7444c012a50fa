#include "tread_wear/ros/bag/replay_config.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <stdexcept>

#include "tread_wear/io/params_io.h"

namespace tread_wear {

namespace {

std::string absoluteTopic(const std::string& topic) { return topic.empty() || topic[0] == '/' ? topic : "/" + topic; }

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

template <typename T>
double number(const YAML::Node& node, const char* key, double fallback) {
  return node[key] ? node[key].as<T>() : fallback;
}

}  // namespace

ReplayConfig loadReplayConfig(const std::string& path) {
  auto fail = [&](const std::string& what) { return std::runtime_error(path + ": " + what); };
  YAML::Node root;
  try {
    std::ifstream probe(path);
    if (!probe) throw fail("cannot open the file for reading");
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw fail(std::string("not a readable YAML document: ") + e.what());
  }
  ReplayConfig c;
  try {
    ReplaySettings& s = c.settings;
    s.update_rate_hz = number<double>(root, "update_rate_hz", s.update_rate_hz);
    if (root["preset"] && !parsePreset(root["preset"].as<std::string>(), &s.model.preset))
      throw fail("preset '" + root["preset"].as<std::string>() + "' is not " + kPresetChoices);
    if (root["turn_slip_orientation"]) {
      const std::string o = root["turn_slip_orientation"].as<std::string>();
      if (!parseOrientation(o, &s.model.orientation))
        throw fail("turn_slip_orientation '" + o + "' is not literal or flipped");
    }
    s.model.min_speed_mps = number<double>(root, "min_speed_mps", s.model.min_speed_mps);
    s.estimator.stale_timeout_s = number<double>(root, "stale_timeout_s", s.estimator.stale_timeout_s);
    s.estimator.max_step_s = number<double>(root, "max_step_s", s.estimator.max_step_s);
    if (const YAML::Node l = root["limits"]) {
      InputLimits& lim = s.estimator.limits;
      lim.max_load_n = number<double>(l, "max_load_n", lim.max_load_n);
      lim.max_abs_slip_angle_rad = number<double>(l, "max_abs_slip_angle_rad", lim.max_abs_slip_angle_rad);
      lim.max_abs_slip_ratio = number<double>(l, "max_abs_slip_ratio", lim.max_abs_slip_ratio);
      lim.max_abs_path_curvature_per_m =
          number<double>(l, "max_abs_path_curvature_per_m", lim.max_abs_path_curvature_per_m);
      lim.max_speed_mps = number<double>(l, "max_speed_mps", lim.max_speed_mps);
      lim.min_temperature_c = number<double>(l, "min_temperature_c", lim.min_temperature_c);
      lim.max_temperature_c = number<double>(l, "max_temperature_c", lim.max_temperature_c);
    }
    const YAML::Node wheels = root["wheels"];
    if (!wheels || !wheels.IsSequence() || wheels.size() == 0) throw fail("key 'wheels' must be a non-empty list");
    for (const YAML::Node& w : wheels) {
      ReplayWheel wheel;
      if (!w["name"] || !w["tire_params"]) throw fail("every entry of 'wheels' needs name and tire_params");
      wheel.name = w["name"].as<std::string>();
      wheel.frame_id = w["frame_id"] ? w["frame_id"].as<std::string>() : wheel.name;
      wheel.tire_id = w["tire_id"] ? w["tire_id"].as<std::string>() : "unknown";
      std::string tire = w["tire_params"].as<std::string>();
      if (tire.empty() || tire[0] != '/') tire = directoryOf(path) + "/" + tire;
      wheel.tire = loadTireParams(tire);
      auto topic = [&](const char* key, const char* leaf) {
        return absoluteTopic(w[key] ? w[key].as<std::string>() : "wheels/" + wheel.name + "/" + leaf);
      };
      c.load_topics.push_back(topic("load_topic", "load"));
      c.slip_topics.push_back(topic("slip_topic", "slip"));
      c.speed_topics.push_back(topic("speed_topic", "speed"));
      c.temperature_topics.push_back(topic("temperature_topic", "tread_temperature"));
      c.wear_topics.push_back(topic("wear_topic", "wear"));
      c.wheels.push_back(std::move(wheel));
    }
  } catch (const YAML::Exception& e) {
    throw fail(std::string("bad value: ") + e.what());
  } catch (const ParamsError& e) {
    throw fail(std::string("tire parameters: ") + e.what());
  }
  std::string error;
  if (!c.settings.validate(&error)) throw fail(error);
  return c;
}

}  // namespace tread_wear
