#pragma once
/// @file node_planner.h
/// The node's planner at the vehicle level (docs/planner.md): the evaluate_trajectories service and the wear map
/// of the latched wear_map topic, over the ROS-free core (planning/trajectory_cost.h, planning/wear_map.h). Like
/// node_services.h it knows ROS only as messages: no node handle, so the tests drive it without a master
/// (test/ros/test_node_planner.cpp); TreadWearNode advertises the service and the topic and calls refresh() on a
/// wall timer.
///
/// Setup: the vehicle (planner/vehicle_params), the tire of the node's wheel at each vehicle place
/// (planner/wheel_names, default front_left, front_right, rear_left, rear_right), the node's model options and input
/// limits, the configured preset (reconfigurable) and the wheels' live tread temperatures. Without vehicle
/// parameters, or when the node's wheels are not a four-wheel car, the planner is unavailable and the service
/// answers success = false with the reason.
///
/// Threads (the update loop is never involved: it neither reads nor waits for anything here):
///   - the map builder: its own thread, low priority in effect (one build thread by default on two shared cores).
///     refresh() (spinner thread) compares the setup it would build now with the map's and, when the preset changed
///     or a known tread temperature moved by more than map_temperature_step_c (only for tires whose wear law uses
///     temperature), hands the builder the new setup; a build in progress for an older setup is cancelled. The new
///     map is swapped in with an atomic shared_ptr store; readers keep the map they loaded until they drop it.
///   - the service (spinner threads): mode map loads the current map (lock-free) and evaluates from it; mode direct
///     evaluates on the planner's own models under the planner's mutex, with the temperatures at call time.

#include <ros/node_handle.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/EvaluateTrajectories.h"
#include "tread_wear/PlannerWearMap.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

// The planning core stays out of this header: its vehicle WheelState and the message tread_wear::WheelState of
// evaluate_wear share a name, and the node includes both services.
class WearMap;

/// The planner's keys under the node's private namespace (planner/...); docs/node.md.
struct NodePlannerConfig {
  static constexpr std::size_t kPlaces = 4;  ///< vehicle wheel places (vehicle_model.h kWheelCount)
  std::string vehicle_params;  ///< vehicle parameter file (config/vehicle_*.yaml); empty = planner unavailable
  /// The node's wheel at each place: front_left, front_right, rear_left, rear_right.
  std::array<std::string, kPlaces> wheel_names{{"front_left", "front_right", "rear_left", "rear_right"}};
  bool build_map = true;                   ///< build and publish the wear map (false: mode direct only)
  double map_temperature_step_c = 5.0;     ///< tread temperature change that rebuilds the map [K], > 0
  double max_path_curvature_per_m = 0.25;  ///< |kappa| bound of a sample [1/m], > 0
  int map_threads = 1;                     ///< threads of a map build [-], >= 1
  /// Map axes (wear_map.h WearMapParams); empty = its defaults. Tests use small grids.
  std::vector<double> map_speed_mps, map_accel_x_mps2, map_lateral_share;

  /// false with *error "<key> = <value>: must be <constraint>" for the first broken constraint.
  bool validate(std::string* error) const;
};

/// Reads planner/vehicle_params (relative paths start at config_dir), planner/wheel_names (a list of 4),
/// planner/build_map, planner/map_temperature_step_c, planner/max_path_curvature_per_m, planner/map_threads.
/// false with *error naming the key for a value out of range.
bool loadNodePlannerConfig(const ros::NodeHandle& pnh, const std::string& config_dir, NodePlannerConfig* config,
                           std::string* error);

class NodePlanner {
 public:
  /// Runs on the builder thread for each new map with its message filled (stamp and frame_id left to the caller).
  using MapCallback = std::function<void(tread_wear::PlannerWearMap& message)>;

  /// Matches the wheels and loads the vehicle; on failure the planner is unavailable (reason()), never throws for
  /// configuration. on_map may be empty.
  NodePlanner(const NodePlannerConfig& config, const std::vector<std::unique_ptr<WheelPipeline>>& wheels,
              const WearModelOptions& model, MapCallback on_map);
  ~NodePlanner();
  NodePlanner(const NodePlanner&) = delete;
  NodePlanner& operator=(const NodePlanner&) = delete;

  bool available() const;
  const std::string& reason() const;  ///< why unavailable (empty when available)

  /// Spinner thread, periodically: the configured preset and the wheels' live temperatures at now_s [s] (node
  /// clock); requests a rebuild when they changed enough (file comment). true when it requested one.
  bool refresh(Preset configured, double now_s);
  /// The current map (nullptr before the first build completes or without build_map). Lock-free.
  std::shared_ptr<const WearMap> map() const;
  /// Builds done since start [-].
  std::uint32_t mapVersion() const;
  /// The last build failure (empty if none).
  std::string buildError() const;

  /// evaluate_trajectories; configured = the node's preset, now_s [s] = the node clock for the live temperatures.
  void evaluate(const tread_wear::EvaluateTrajectories::Request& request, Preset configured, double now_s,
                tread_wear::EvaluateTrajectories::Response* response);

  /// Stops the builder (cancels a build in progress); idempotent, also called by the destructor.
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The map as its latched message (frame_id and stamp set by the caller), wheels named as the node names them.
void fillWearMapMessage(const WearMap& map, std::uint32_t version,
                        const std::array<std::string, NodePlannerConfig::kPlaces>& wheels,
                        tread_wear::PlannerWearMap* message);

}  // namespace tread_wear
