#pragma once
/// @file wheel_config.h
/// The wheel configuration (config/vehicle_wheels.yaml, docs/node.md): one defaults table, one reader and one
/// validation for both of its users. tread_wear_node gets the document from the parameter server (the launch file
/// loads the YAML into its private namespace; src/ros/node_config.cpp turns that XML-RPC tree into a ConfigValue) and
/// tread_wear_replay from the file (loadNodeConfigFile); both call readNodeConfig(), so a key, its default and its
/// constraint cannot differ between the live node and the offline replay. ROS-free.

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {

/// A configuration document as both sources deliver it (a YAML file, the parameter server's XML-RPC tree): null,
/// boolean, number, string, list or map. Integers and reals are both numbers [in the key's unit].
struct ConfigValue {
  enum class Type { kNull, kBool, kNumber, kString, kList, kMap };
  Type type = Type::kNull;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<ConfigValue> list;
  std::map<std::string, ConfigValue> map;

  /// The value as a message shows it: strings quoted, lists [a, b], maps {key: value}.
  std::string text() const;
};

/// Longest tire id [characters]: the node's real-time loop copies it into preallocated message strings.
constexpr std::size_t kMaxTireIdLength = 63;

/// One wheel: where its inputs come from, which tire it has, where its outputs go.
struct WheelConfig {
  std::string name;         ///< wheel name, unique (e.g. front_left)
  std::string frame_id;     ///< tf frame at the contact centre, ISO 8855 tire axes (x fwd, y left, z up); default name
  std::string tire_params;  ///< tire parameter file (params_io.h); relative paths are joined to config_dir
  std::string tire_id = "unknown";  ///< id of the mounted tire when no saved state exists, 1..kMaxTireIdLength chars
  /// Input and output topics; default wheels/<name>/{load,slip,speed,tread_temperature,wear}.
  std::string load_topic, slip_topic, speed_topic, temperature_topic, wear_topic;
  bool has_position = false;  ///< position_m given: the node broadcasts a static base_frame -> frame_id tf
  std::array<double, 3> position_m{{0.0, 0.0, 0.0}};  ///< contact centre in base_frame [m]
};

/// Every key of the wheel configuration. The member initialisers are the defaults of the node and the replay.
struct NodeConfig {
  double update_rate_hz = 100.0;  ///< update loop rate [Hz], in (0, 1000], >= 2 / max_step_s
  double marker_rate_hz = 5.0;    ///< rviz marker rate [Hz], in [0, update_rate_hz] (0 = off)
  double budget_us = 0.0;         ///< time budget per wheel evaluation [us], >= 0 (0 = none); node only
  WearModelOptions model;         ///< keys preset, turn_slip_orientation, min_speed_mps (others keep their defaults)
  WheelEstimatorParams estimator;  ///< keys stale_timeout_s, max_step_s, limits/*
  std::string state_file;         ///< persistence file; empty = no persistence
  double save_interval_s = 10.0;  ///< period of state saves [s] (wall clock), > 0
  std::string base_frame = "base_link";  ///< frame of the aggregate message and of wheel positions
  std::string config_dir;         ///< directory that relative tire_params paths start from ("" = working directory)
  std::vector<WheelConfig> wheels;  ///< at least one

  /// false with *error as "<key> = <value>: must be <constraint>" for the first broken constraint.
  bool validate(std::string* error) const;
  /// One line per key with its value and unit, for the node's INFO echo at start-up.
  std::string describe() const;
};

/// Reads a wheel configuration document (a map of the keys of docs/node.md). Absent keys keep NodeConfig's
/// defaults; config_dir defaults to default_config_dir. Relative tire_params are joined to config_dir. Validates.
/// false with *error naming the key, the value and the broken constraint (wrong type, unknown name, invalid value).
bool readNodeConfig(const ConfigValue& document, const std::string& default_config_dir, NodeConfig* config,
                    std::string* error);

/// A YAML file as the tree the parameter server would hold after `rosparam load` (booleans and numbers as rosparam
/// reads them, quoted scalars strings). @throw std::runtime_error "<path>: <what>" for an unreadable file or bad YAML
ConfigValue loadConfigDocument(const std::string& path);

/// Reads a YAML wheel configuration file through readNodeConfig(); config_dir defaults to the file's directory.
/// @throw std::runtime_error "<path>: <what>" for an unreadable file, bad YAML or an invalid configuration
NodeConfig loadNodeConfigFile(const std::string& path);

/// The keys with their defaults, units and meanings, one per line (tread_wear_node --help).
std::string nodeConfigKeysHelp();

}  // namespace tread_wear
