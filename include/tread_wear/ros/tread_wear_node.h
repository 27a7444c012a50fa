#pragma once
/// @file tread_wear_node.h
/// ROS wrapper of the per-wheel wear estimator (core/wheel_estimator.h): subscriptions, the fixed-rate
/// update loop, outputs, the planner and reset services, persistence, diagnostics, rviz markers and
/// dynamic_reconfigure. Topics, parameters and diagnostics: docs/node.md.
///
/// Threads:
///   - ROS spinner threads (global queue): input callbacks, services, diagnostics, markers, saving,
///     dynamic_reconfigure. Allowed to allocate and log.
///   - the update loop (own callback queue and thread): per cycle it copies each wheel's inputs under a
///     short per-wheel lock, steps the estimator (one model evaluation per wheel) and hands preallocated
///     messages to RealtimePublishers with try_lock. No allocation, logging or I/O; counters only, which the
///     diagnostics timer turns into diagnostics and throttled warnings.

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <boost/thread/recursive_mutex.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tread_wear/EvaluateWear.h"
#include "tread_wear/ResetWheel.h"
#include "tread_wear/TreadTemperature.h"
#include "tread_wear/TreadWearConfig.h"
#include "tread_wear/VehicleWear.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/WheelWear.h"
#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/io/state_store.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/ros/node_config.h"
#include "tread_wear/ros/realtime_publisher.h"

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
  /// Everything about one wheel. Locks: input_mutex (callbacks <-> loop, copy only), state_mutex
  /// (loop <-> services/diagnostics/saving/markers, copy only).
  struct Wheel {
    WheelConfig config;
    std::unique_ptr<WearModel> model;          ///< live model, used by the loop only
    std::unique_ptr<WearModel> planner_model;  ///< planner service model (guarded by planner_mutex)
    std::unique_ptr<WearModel> marker_model;   ///< rviz model (marker timer only)
    std::mutex planner_mutex;
    std::mutex input_mutex;
    WheelInputs inputs;                        ///< guarded by input_mutex
    WheelInputs loop_inputs;                   ///< the loop's copy
    std::mutex state_mutex;
    std::unique_ptr<WheelEstimator> estimator;  ///< stepped by the loop under state_mutex
    std::string tire_id;                        ///< guarded by state_mutex
    double reset_unix_s = 0.0;                  ///< guarded by state_mutex
    bool tire_id_changed = true;                ///< guarded by state_mutex: copy tire_id into the message
    WheelInputs last_step_inputs;               ///< inputs of the last step, guarded by state_mutex
    std::atomic<std::uint64_t> overruns{0};     ///< evaluations longer than the budget [-]
    std::atomic<double> last_eval_us{0.0};      ///< duration of the last evaluation [us]
    std::atomic<double> max_eval_us{0.0};       ///< longest evaluation since start [us]
    std::atomic<int> active_preset{1};          ///< preset of the last evaluation (the budget may degrade it)
    std::atomic<long> degraded_count{0};        ///< evaluations coarser than the configured preset [-]
    std::unique_ptr<RealtimePublisher<tread_wear::WheelWear>> publisher;
    ros::Subscriber load_sub, slip_sub, speed_sub, temperature_sub;
    // Diagnostics bookkeeping (diagnostics timer only).
    std::array<std::uint64_t, kInputKindCount> last_received{};
    std::uint64_t last_rejected = 0, last_backward = 0, last_forward = 0;
    double last_diag_wall_s = 0.0;
  };

  bool loadWheel(const WheelConfig& config, Wheel* wheel);
  void restoreState();
  void loop(const ros::TimerEvent& event);
  void fillWheelMessage(Wheel& wheel, const WheelOutput& out, const ros::Time& stamp, tread_wear::WheelWear* msg);
  void countOverrun(Wheel& wheel, double eval_us);
  bool evaluateWear(tread_wear::EvaluateWear::Request& req, tread_wear::EvaluateWear::Response& res);
  bool resetWheel(tread_wear::ResetWheel::Request& req, tread_wear::ResetWheel::Response& res);
  void saveState(const char* reason);
  void publishMarkers(const ros::TimerEvent& event);
  void diagnoseWheel(Wheel& wheel, diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnoseLoop(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnosePersistence(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void reconfigure(tread_wear::TreadWearConfig& config, uint32_t level);
  void broadcastWheelFrames();

  ros::NodeHandle nh_, pnh_;
  NodeConfig config_;
  std::vector<std::unique_ptr<Wheel>> wheels_;
  std::unique_ptr<StateStore> store_;
  StateFile saved_state_;  ///< last loaded/saved file content (keeps wheels not configured now)
  std::mutex save_mutex_;
  std::string persistence_problem_;  ///< guarded by save_mutex_; empty = fine
  std::string restore_report_;       ///< what happened at start-up (for diagnostics)
  double last_save_wall_s_ = 0.0;    ///< guarded by save_mutex_

  // Update loop.
  ros::CallbackQueue loop_queue_;
  ros::Timer loop_timer_;
  std::thread loop_thread_;
  std::atomic<bool> loop_running_{false};
  std::atomic<double> period_s_{0.01};
  std::atomic<double> budget_us_{0.0};
  std::atomic<int> configured_preset_{1};
  std::atomic<std::uint64_t> cycles_{0}, cycle_overruns_{0};
  std::atomic<double> last_cycle_us_{0.0}, max_cycle_us_{0.0};
  std::unique_ptr<RealtimePublisher<tread_wear::VehicleWear>> vehicle_publisher_;

  ros::ServiceServer evaluate_service_, reset_service_;
  ros::WallTimer save_timer_, diagnostics_timer_;
  ros::Timer marker_timer_;
  ros::Publisher marker_publisher_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<dynamic_reconfigure::Server<tread_wear::TreadWearConfig>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;  // dynamic_reconfigure::Server requires this type
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> tf_broadcaster_;
  std::atomic<bool> shut_down_{false};
  std::uint64_t last_cycle_overruns_ = 0;  ///< diagnostics timer only
};

}  // namespace tread_wear
