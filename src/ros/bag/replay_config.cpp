#include "tread_wear/ros/bag/replay_config.h"

#include <stdexcept>

#include "tread_wear/io/params_io.h"
#include "tread_wear/io/wheel_config.h"

namespace tread_wear {

namespace {

/// Bag topics are absolute: the node they replace runs in the root namespace, where its relative names resolve so.
std::string absoluteTopic(const std::string& topic) { return topic.empty() || topic[0] == '/' ? topic : "/" + topic; }

}  // namespace

ReplayConfig loadReplayConfig(const std::string& path) {
  const NodeConfig node = loadNodeConfigFile(path);
  ReplayConfig c;
  c.settings.update_rate_hz = node.update_rate_hz;
  c.settings.model = node.model;
  c.settings.estimator = node.estimator;
  for (const WheelConfig& w : node.wheels) {
    ReplayWheel wheel;
    wheel.name = w.name;
    wheel.frame_id = w.frame_id;
    wheel.tire_id = w.tire_id;
    try {
      wheel.tire = loadTireParams(w.tire_params);
    } catch (const ParamsError& e) {
      throw std::runtime_error(path + ": tire parameters: " + e.what());
    }
    c.load_topics.push_back(absoluteTopic(w.load_topic));
    c.slip_topics.push_back(absoluteTopic(w.slip_topic));
    c.speed_topics.push_back(absoluteTopic(w.speed_topic));
    c.temperature_topics.push_back(absoluteTopic(w.temperature_topic));
    c.wear_topics.push_back(absoluteTopic(w.wear_topic));
    c.wheels.push_back(std::move(wheel));
  }
  std::string error;
  if (!c.settings.validate(&error)) throw std::runtime_error(path + ": " + error);
  return c;
}

}  // namespace tread_wear
