#pragma once
/// @file replay_config.h
/// The replay's configuration: the node's YAML (config/vehicle_wheels.yaml), read without a ROS master.

#include <string>
#include <vector>

#include "tread_wear/estimation/drive_replay.h"

namespace tread_wear {

/// Replay configuration: the estimation keys of the node's YAML and its wheels.
struct ReplayConfig {
  ReplaySettings settings;
  std::vector<ReplayWheel> wheels;
  std::vector<std::string> load_topics, slip_topics, speed_topics, temperature_topics, wear_topics;  ///< per wheel
};

/// Reads the node configuration file through the node's own reader (io/wheel_config.h: the same keys, defaults
/// and validation as tread_wear_node) and loads each wheel's tire file. Relative tire_params start at the file's
/// directory unless the file sets config_dir; topics are made absolute. @throw std::runtime_error naming the file and
/// the key
ReplayConfig loadReplayConfig(const std::string& path);

}  // namespace tread_wear
