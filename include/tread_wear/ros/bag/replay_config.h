#pragma once
/// @file replay_config.h
/// The replay's configuration, read from the node's YAML (config/vehicle_wheels.yaml) without a ROS master.

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

/// Reads the node configuration file (keys of docs/node.md: update_rate_hz, preset, turn_slip_orientation,
/// min_speed_mps, stale_timeout_s, max_step_s, limits, wheels[name, frame_id, tire_params, tire_id, *_topic]).
/// Relative tire_params start at the file's directory. @throw std::runtime_error naming the file and key
ReplayConfig loadReplayConfig(const std::string& path);

}  // namespace tread_wear
