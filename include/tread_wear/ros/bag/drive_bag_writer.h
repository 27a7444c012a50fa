#pragma once
/// @file drive_bag_writer.h
/// A generated test drive written as the node's input topics, and the drive bag's format (metadata topic, time
/// offset), which drive_bag_reader.h reads.

#include <cstddef>
#include <string>
#include <vector>

#include "tread_wear/io/drive_info_json.h"
#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/vehicle/drive_motion.h"
#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/sensor_model.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

/// Topic of the drive's metadata (std_msgs/String, the JSON document of io/drive_info_json.h).
constexpr const char* kDriveInfoTopic = "/drive/info";
/// Bag time of drive time 0 [s]: ros::Time(0) means "unset" to ROS, so drives start later.
constexpr double kDriveTimeOffset_s = 1000.0;

/// Options of a generated drive.
struct DriveOptions {
  double rate_hz = 50.0;                   ///< sample rate of every input topic [Hz], > 0
  std::vector<std::string> wheel_names;    ///< topic names wheels/<name>/..., in vehicle wheel order (4)
  bool sensors = false;                    ///< also write the car's sensor topics (writeSensorTopics)
  SensorModelParams sensor_params;         ///< their sensor model (vehicle/sensor_model.h)
};

/// Sensor topics of a drive with options.sensors (the contract of the vehicle_inputs front end,
/// docs/vehicle_inputs.md): sensor_msgs/Imu on kImuTopic (frame kImuFrame), sensor_msgs/JointState on
/// kJointStatesTopic (wheel velocities [rad/s] and the steering-wheel position [rad] of kJointNames),
/// nav_msgs/Odometry on kOdometryTopic (twist.twist.linear.x [m/s]; header stamp = measurement time, record time =
/// stamp + odometry_lag_s), and the mount base_link -> imu_link once on /tf_static. Header stamps are measurement
/// times, bag time = drive time + kDriveTimeOffset_s as for the truth topics.
constexpr const char* kImuTopic = "/imu";
constexpr const char* kJointStatesTopic = "/joint_states";
constexpr const char* kOdometryTopic = "/odom";
constexpr const char* kBaseFrame = "base_link";
constexpr const char* kImuFrame = "imu_link";
constexpr const char* kOdometryFrame = "odom";
/// Joint names of joint_states: the four wheels in vehicle order, then the steering wheel.
constexpr const char* kJointNames[kWheelCount + 1] = {"wheel_front_left_joint", "wheel_front_right_joint",
                                                      "wheel_rear_left_joint", "wheel_rear_right_joint",
                                                      "steering_wheel_joint"};

/// The wear node's input topics of one wheel and the frame of their headers (docs/node.md).
struct WheelInputTopics {
  std::string load, slip, speed, frame;
};
/// The input topics of the wheel called `name`: /wheels/<name>/{load,slip,speed}, frame wheel_<name>.
WheelInputTopics wheelInputTopics(const std::string& name);

/// Statistics of a written drive.
struct DriveStats {
  std::size_t samples = 0;        ///< time samples (each with all topics of all wheels) [-]
  double duration_s = 0.0;        ///< [s]
  double distance_m = 0.0;        ///< [m]
  double max_abs_lateral_accel_mps2 = 0.0;  ///< [m/s^2]
  double max_abs_accel_mps2 = 0.0;          ///< largest |a_x| over the samples [m/s^2]
};

/// Writes the drive: for each of the 4 wheels load, slip and speed at rate_hz, header and record time = drive
/// time + kDriveTimeOffset_s, plus the metadata on kDriveInfoTopic; with options.sensors also the sensor topics
/// above (same drive, its own sample rates). The metadata describes the drive as `description` says (its duration
/// and distance are the motion's), with the route of the motion built with route_params.
/// @throw BagError when the file cannot be written
DriveStats writeDriveBag(const std::string& path, const DriveMotion& motion, const DriveDescription& description,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options);
/// The profile driven as it prescribes over the route (ProfileMotion), named and phased as the profile.
DriveStats writeDriveBag(const std::string& path, const SpeedProfile& profile, const Route& route,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options);

}  // namespace tread_wear
