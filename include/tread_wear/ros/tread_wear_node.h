#pragma once
/// @file tread_wear_node.h
/// tread_wear_node: composes the node's parts and owns the ROS handles that connect them. Topics, parameters,
/// services and diagnostics: docs/node.md.
///
/// Parts, each in its own file pair and tested alone (test/ros/test_node_parts.cpp):
///   configuration  node_config.h (parameter server -> io/wheel_config.h, shared with the replay)
///   per wheel      pipeline/wheel_pipeline.h (inputs, live model and estimator, planner model), its message
///                  wheel_pipeline.h
///   persistence    pipeline/node_persistence.h;  services  node_services.h;  diagnostics  node_diagnostics.h
///   planner        node_planner.h (evaluate_trajectories, wear_map; its map builder thread)
///   markers        wear_markers.h;      reconfigure  node_reconfigure.h;  publishing  realtime_publisher.h
///
/// Threads:
///   - ROS spinner threads (global queue): input callbacks, services, diagnostics, markers, saving,
///     dynamic_reconfigure. Allowed to allocate and log.
///   - the update loop (own callback queue and thread): per cycle each wheel's pipeline steps once and the
///     preallocated messages go to RealtimePublishers with try_lock. No allocation, logging or I/O; counters only
///     (LoopStatus), which diagnostics turns into reports and throttled warnings.

#include <dynamic_reconfigure/server.h>
#include <boost/thread/recursive_mutex.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "tread_wear/TreadWearConfig.h"
#include "tread_wear/VehicleWear.h"
#include "tread_wear/WheelWear.h"
#include "tread_wear/io/wheel_config.h"
#include "tread_wear/pipeline/node_persistence.h"
#include "tread_wear/ros/loop_status.h"
#include "tread_wear/ros/node_diagnostics.h"
#include "tread_wear/ros/node_planner.h"
#include "tread_wear/ros/node_reconfigure.h"
#include "tread_wear/ros/realtime_publisher.h"
#include "tread_wear/ros/wear_markers.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

class TreadWearNode {
 public:
  TreadWearNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  ~TreadWearNode();

  /// Loads the configuration and tire files, restores the state, starts everything.
  /// false (after logging the reason) when the node cannot run.
  bool initialize();
  /// Stops the loop and saves the state; idempotent, also called by the destructor.
  void shutdown();

 private:
  void subscribeInputs(WheelPipeline* wheel);
  void loop();
  /// Simulated time: how far the inputs are processed, on input_progress (InputProgress.msg), which replay.launch's
  /// rosbag play follows (--rate-control-topic) so that a replay never runs ahead of the node.
  void publishProgress();
  /// Simulated time, until the replay starts: waits for the required inputs' publishers, then starts input_progress
  /// and resumes the paused player (~replay_resume_service, launch/replay.launch).
  void startReplay();
  void publishMarkers(const ros::TimerEvent& event);
  void reconfigure(tread_wear::TreadWearConfig& config);
  void broadcastWheelFrames();
  void startPlanner();
  /// Deadline of one evaluation [us]: the budget when set, else the wheel's share of the update period.
  double evaluationDeadline_us() const;
  /// What a wheel's step needs besides its time, from the loop's live settings.
  WheelPipeline::StepSettings stepSettings() const;

  ros::NodeHandle nh_, pnh_;
  NodeConfig config_;
  std::vector<std::unique_ptr<WheelPipeline>> wheels_;
  LoopStatus loop_status_;
  std::unique_ptr<NodePersistence> persistence_;
  std::unique_ptr<NodeReconfigure> reconfigure_;
  std::unique_ptr<NodeDiagnostics> diagnostics_;
  std::unique_ptr<WearMarkers> markers_;

  // Update loop: its queue, timer and thread, and the messages it fills (one per wheel, one for the vehicle).
  ros::CallbackQueue loop_queue_;
  ros::Timer loop_timer_;           ///< live: the update loop on the node clock
  ros::WallTimer loop_wall_timer_;  ///< simulated time: the publication loop on wall time
  /// Simulated time: input_progress every kProgressPeriod_s of wall time [s] (often enough that rosbag play, which
  /// holds back while the progress is more than its rate-control delay behind, rarely waits on the timer itself).
  static constexpr double kProgressPeriod_s = 0.01;
  ros::WallTimer progress_timer_;
  ros::Publisher progress_publisher_;
  /// The longest wait for the required inputs' publishers before the replay starts anyway, and how long they must
  /// all have been connected before it starts [s of wall time].
  static constexpr double kConnectWait_s = 10.0, kConnectSettle_s = 0.5;
  ros::WallTimer start_timer_;
  ros::WallTime progress_start_, connected_since_;
  std::atomic<bool> inputs_connected_{false};  ///< the replay has started (startReplay)
  std::string resume_service_;  ///< the player's pause service (~replay_resume_service), "" for none
  std::atomic<double> last_input_stamp_s_{0.0};  ///< stamp of the last input sample processed [s]
  std::thread loop_thread_;
  std::atomic<bool> loop_running_{false};
  std::vector<std::unique_ptr<RealtimePublisher<tread_wear::WheelWear>>> wheel_publishers_;
  std::unique_ptr<RealtimePublisher<tread_wear::VehicleWear>> vehicle_publisher_;

  std::vector<ros::Subscriber> input_subscribers_;
  std::vector<ros::Subscriber> required_subscribers_;  ///< load, slip and speed of every wheel
  ros::ServiceServer evaluate_service_, reset_service_;
  ros::WallTimer save_timer_, diagnostics_timer_;
  ros::Timer marker_timer_;
  ros::Publisher marker_publisher_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  boost::recursive_mutex reconfigure_mutex_;  // dynamic_reconfigure::Server requires this type; outlives the server
  std::unique_ptr<dynamic_reconfigure::Server<tread_wear::TreadWearConfig>> reconfigure_server_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
  // Planner at the vehicle level (node_planner.h): evaluate_trajectories and the latched wear_map.
  std::unique_ptr<NodePlanner> planner_;
  ros::ServiceServer trajectories_service_;
  ros::Publisher map_publisher_;
  ros::WallTimer planner_timer_;
  std::atomic<bool> shut_down_{false};
};

}  // namespace tread_wear
