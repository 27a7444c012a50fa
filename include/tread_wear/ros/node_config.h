#pragma once
/// @file node_config.h
/// Parameters of tread_wear_node, read from the node's private namespace (loaded from config/*.yaml by the
/// launch file). Every key and its unit: docs/node.md and the comments in config/vehicle_wheels.yaml.

#include <ros/node_handle.h>

#include <array>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {

/// One wheel: where its inputs come from, which tire it has, where its outputs go.
struct WheelConfig {
  std::string name;                ///< wheel name, unique (e.g. front_left)
  std::string frame_id;            ///< tf frame at the contact centre, ISO 8855 tire axes (x fwd, y left, z up)
  std::string tire_params;         ///< tire parameter file (params_io.h); relative paths from config_dir
  std::string tire_id;             ///< id of the mounted tire when no saved state exists
  std::string load_topic, slip_topic, speed_topic, temperature_topic, wear_topic;  ///< topic names
  bool has_position = false;       ///< position_m given: the node broadcasts a static base_frame -> frame_id tf
  std::array<double, 3> position_m{{0.0, 0.0, 0.0}};  ///< contact centre in base_frame [m]
};

struct NodeConfig {
  double update_rate_hz = 100.0;      ///< update loop rate [Hz], > 0
  double marker_rate_hz = 5.0;        ///< rviz marker rate [Hz], >= 0 (0 = off), <= update_rate_hz
  double budget_us = 0.0;             ///< time budget per wheel evaluation [us], >= 0 (0 = none)
  Preset preset = Preset::kStandard;  ///< finest model preset
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;  ///< slip angle vs path curve
  double min_speed_mps = 0.1;         ///< low-speed threshold of the wear model [m/s]
  WheelEstimatorParams estimator;     ///< stale timeout [s], time-jump threshold [s], input limits
  std::string state_file;             ///< persistence file; empty = no persistence
  double save_interval_s = 10.0;      ///< period of state saves [s] (wall clock), > 0
  std::string base_frame = "base_link";  ///< frame of the aggregate message and of wheel positions
  std::string config_dir;             ///< directory that relative tire_params paths start from
  std::vector<WheelConfig> wheels;

  bool validate(std::string* error) const;
  /// Reads everything from a private NodeHandle; false with *error naming the key on a bad or missing value.
  static bool load(const ros::NodeHandle& pnh, NodeConfig* config, std::string* error);
  /// One line per parameter, for the INFO echo at start-up.
  std::string describe() const;
};

}  // namespace tread_wear
