#pragma once
/// @file vehicle_inputs_config.h
/// Configuration of vehicle_inputs_node (docs/vehicle_inputs_node.md): topics, joint names, frames, rate,
/// persistence, and the estimator's parameters (estimation/vehicle_input_estimator.h) with the vehicle parameters
/// from a vehicle file (io/vehicle_params_io.h). One table of defaults (the struct's initialisers), one validate().

#include <ros/node_handle.h>

#include <array>
#include <string>

#include "tread_wear/estimation/vehicle_input_estimator.h"

namespace tread_wear {

struct VehicleInputsConfig {
  double publish_rate_hz = 100.0;          ///< fixed publication rate [Hz], (0, 1000]
  std::string speed_source = "odom";       ///< reference speed: "odom" (nav_msgs/Odometry on `odom`) or "twist"
                                           ///< (geometry_msgs/TwistWithCovarianceStamped on `speed`)
  std::string base_frame = "base_link";    ///< body frame (REP-103: x forward, y left, z up)
  std::array<double, 3> cog_position_m{{0.0, 0.0, 0.55}};  ///< CoG in base_frame [m] (default z = cog_height_m)
  bool cog_position_set = false;           ///< cog_position_m given as a parameter (else z = the vehicle's h)
  std::array<std::string, kWheelCount> wheel_names{{"front_left", "front_right", "rear_left", "rear_right"}};
  std::array<std::string, kWheelCount> wheel_joints{
      {"wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint", "wheel_rear_right_joint"}};
  std::array<double, kWheelCount> wheel_velocity_signs{{1.0, 1.0, 1.0, 1.0}};  ///< joint velocity x sign = forward
                                           ///< wheel speed [-], each +1 or -1 (a mirrored joint axis: -1)
  std::array<std::string, kWheelCount> wheel_frames{
      {"wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right"}};  ///< for the rviz labels
  std::string steering_joint = "steering_wheel_joint";  ///< steering-wheel joint, position [rad], > 0 left
  double tf_timeout_s = 0.0;               ///< wait for a sensor transform in its callback [s], [0, 1] (blocks the
                                           ///< callbacks and the cycle: keep 0 unless the transform comes late)
  std::string vehicle_params_file;         ///< config/vehicle_*.yaml, required
  std::string radius_file;                 ///< learned rolling radii (JSON); empty = not persisted
  double save_interval_s = 30.0;           ///< period of radius saves (wall clock) [s], > 0; also on shutdown
  double diagnostic_period_s = 1.0;        ///< /diagnostics period [s], > 0
  double marker_rate_hz = 5.0;             ///< rviz `vehicle_markers` rate [Hz], 0 = off, <= publish_rate_hz
  VehicleInputEstimatorParams estimator;   ///< vehicle part from vehicle_params_file, the rest under estimator/

  /// Names the key, the value and the broken constraint of the first invalid setting.
  bool validate(std::string* error) const;
  /// Every value in use, one `key: value` a line (logged at start-up).
  std::string describe() const;
};

/// Reads the private namespace (defaults for absent keys; the vehicle from vehicle_params_file) and validates.
/// false with *error naming the key (a value of the wrong type, an unreadable vehicle file, validate()).
bool loadVehicleInputsConfig(const ros::NodeHandle& pnh, VehicleInputsConfig* config, std::string* error);

}  // namespace tread_wear
