#pragma once
/// @file vehicle_inputs_node.h
/// ROS driver of VehicleInputPipeline (estimation/vehicle_input_pipeline.h): from the car's own sensors
/// (sensor_msgs/Imu, sensor_msgs/JointState with the wheel speeds and the steering-wheel angle, and a reference
/// speed from nav_msgs/Odometry or geometry_msgs/TwistWithCovarianceStamped) to the wear node's per-wheel inputs
/// wheels/<name>/{load,slip,speed} plus wheels/<name>/input_quality, at a fixed rate. docs/vehicle_inputs_node.md.
///
/// Time: every sample enters the pipeline at its header stamp (not its arrival time); the cycle estimates at the
/// node's clock (ros::Time::now(), the bag's time under use_sim_time), or with input_time in the samples' own stamps
/// (the pipeline's grid: the same per-wheel inputs as tread_wear_vehicle_inputs on the same bag). The IMU's mount is
/// the IMU frame's transform from tf2 (VehicleInputPipeline::setImuMount). Without a transform the IMU is not used
/// (the estimator's fallback, a diagnostic), never identity.
/// Threads: every callback and the cycle run on one spinner thread (no locks on the estimator); the publishers'
/// threads serialise (RealtimePublisher). The cycle allocates nothing, logs nothing and does no blocking I/O.

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/TwistWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include "tread_wear/WheelInputQuality.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/WheelWear.h"
#include "tread_wear/estimation/vehicle_input_pipeline.h"
#include "tread_wear/ros/realtime_publisher.h"
#include "tread_wear/ros/vehicle_inputs_config.h"

namespace tread_wear {

/// Fills the quality message of one wheel from the estimate's record (inputQuality, estimation/vehicle_input_pipeline.h;
/// no allocation: the wheel name is set once).
void fillInputQuality(const VehicleInputEstimate& estimate, int wheel, bool published,
                      tread_wear::WheelInputQuality* msg);

/// rviz markers of the car in base_frame (not real-time; allocates): ns "vehicle/body" a translucent box over the
/// wheelbase and tracks, "vehicle/wheels" the four wheels (cylinders at the wheel centres, the front ones turned by
/// their steer angle), "vehicle/label" speed [m/s], yaw rate [rad/s], lateral and longitudinal specific force
/// [m/s^2] and the sources in use. Wheel x = cog_x + l_f | cog_x - l_r, y = cog_y +- t/2.
/// ns "vehicle/wheel_labels": per wheel, in its wheel frame (config.wheel_frames) beside the tire: name, load [kN],
/// slip angle [deg], slip ratio [-] and, when known (finite), the wear node's wear rate [mg/km] and accumulated
/// loss [mg].
struct WheelWearView {
  double wear_rate_kg_per_m = std::numeric_limits<double>::quiet_NaN();  ///< W_r from wheels/<name>/wear [kg/m]
  double accumulated_loss_kg = std::numeric_limits<double>::quiet_NaN(); ///< [kg]
};
void appendVehicleMarkers(const VehicleInputsConfig& config, const VehicleInputEstimate& estimate,
                          const std::array<WheelWearView, kWheelCount>& wear, const ros::Time& stamp,
                          visualization_msgs::MarkerArray* array);

/// Statistics of the publish cycle (read by the diagnostics on the same thread).
struct CycleStats {
  std::uint64_t cycles = 0;
  double last_cpu_us = 0.0, max_cpu_us = 0.0, sum_cpu_us = 0.0;  ///< thread CPU time per cycle [us]
  double last_wall_us = 0.0, max_wall_us = 0.0;                  ///< wall time per cycle [us]
  std::uint64_t overruns = 0;       ///< cycles longer than the period, or started more than a period late
  std::uint64_t skipped_publications = 0;  ///< a publisher thread still held the previous message
  std::uint64_t clock_faults = 0;   ///< estimate() refused a backward or non-finite time
  std::uint64_t invalid_cycles = 0; ///< cycles without any speed source (nothing published)
  std::array<std::uint64_t, kWheelCount> published{}, withheld{};  ///< per wheel: published / not publishable
};

/// One wheel's output publishers (preallocated messages; wheel name and frame ids set once).
struct VehicleInputPublishers {
  std::unique_ptr<RealtimePublisher<tread_wear::WheelLoad>> load;
  std::unique_ptr<RealtimePublisher<tread_wear::WheelSlip>> slip;
  std::unique_ptr<RealtimePublisher<tread_wear::WheelSpeed>> speed;
  std::unique_ptr<RealtimePublisher<tread_wear::WheelInputQuality>> quality;
};

/// The publication step of the cycle: per wheel, load/slip/speed when wheelPublishable() (else none), and always the
/// quality message, stamped `now`; counts published, withheld and skipped (publisher busy) in *stats. Allocates
/// nothing, logs nothing, never blocks (try_lock hand-over); with wait_for_slot (input time, off the real-time path,
/// where a skipped message would be a lost cycle) it waits for each publisher instead.
void publishWheelInputs(const VehicleInputEstimate& estimate, const ros::Time& now,
                        std::array<VehicleInputPublishers, kWheelCount>* publishers, CycleStats* stats,
                        bool wait_for_slot = false);

class VehicleInputsNode {
 public:
  VehicleInputsNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  ~VehicleInputsNode();
  /// Reads and validates the configuration, restores the radii, subscribes, advertises and starts the timers.
  /// false (after logging FATAL with the reason) on an invalid configuration.
  bool initialize();
  /// Stops the timers and saves the radii; idempotent.
  void shutdown();

 private:
  bool imuTransform(const std::string& frame_id);
  /// Input time: the cycles due before a sample stamped `stamp`, each published at its own time.
  void inputTimeCycles(InputStream stream, const ros::Time& stamp);
  void imuCallback(const sensor_msgs::Imu::ConstPtr& msg);
  void jointCallback(const sensor_msgs::JointState::ConstPtr& msg);
  void odomCallback(const nav_msgs::Odometry::ConstPtr& msg);
  void twistCallback(const geometry_msgs::TwistWithCovarianceStamped::ConstPtr& msg);
  void cycle(const ros::TimerEvent& event);
  void saveRadii(const char* why);
  void publishMarkers(const ros::TimerEvent& event);
  void sensorDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void wheelDiagnostics(int wheel, diagnostic_updater::DiagnosticStatusWrapper& stat);
  void cycleDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void radiusDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  ros::NodeHandle nh_, pnh_;
  VehicleInputsConfig config_;
  std::unique_ptr<VehicleInputPipeline> pipeline_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Subscriber imu_sub_, joint_sub_, speed_sub_;
  std::array<VehicleInputPublishers, kWheelCount> publishers_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::Timer cycle_timer_, marker_timer_;
  ros::Publisher marker_pub_;
  std::array<ros::Subscriber, kWheelCount> wear_subs_;
  std::array<WheelWearView, kWheelCount> wear_{};
  ros::WallTimer diagnostics_timer_, save_timer_;
  bool shut_down_ = false;

  // IMU mounting from tf
  std::string imu_frame_;            ///< frame of the cached transform
  bool imu_tf_ok_ = false;
  std::string imu_tf_error_ = "no IMU message yet";
  std::string imu_frame_attempted_;  ///< frame of the last lookup attempt
  ros::WallTime last_tf_attempt_;
  std::uint64_t imu_received_ = 0, imu_without_tf_ = 0;
  std::array<std::uint64_t, kSensorCount> rejected_at_last_report_{};

  CycleStats stats_;

  // rolling radii persistence
  std::string radius_restore_ = "off";
  std::string radius_save_error_;
  ros::WallTime last_save_;
};

}  // namespace tread_wear
