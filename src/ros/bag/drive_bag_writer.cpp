#include "tread_wear/ros/bag/drive_bag_writer.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/drive_info_json.h"
#include "tf_static_message.h"

namespace tread_wear {
namespace {

/// Sample count of a rate over the drive (as the truth topics: both ends included).
std::size_t sampleCount(const DriveMotion& drive, double rate_hz) {
  return static_cast<std::size_t>(std::floor(drive.duration_s() * rate_hz + 1e-9)) + 1;
}

void writeSensorTopics(rosbag::Bag* bag, const DriveMotion& drive, const VehicleModel& vehicle,
                       const SensorModelParams& params) {
  SensorModel sensors(params, vehicle.params().gravity_mps2);
  const double t0 = drive.startTime_s();
  auto motionAt = [&](double t) { return drive.at(t); };
  VehicleState state;

  TfStaticMessage tf;
  tf.transforms.resize(1);
  geometry_msgs::TransformStamped& mount = tf.transforms[0];
  mount.header.stamp = ros::Time(kDriveTimeOffset_s);
  mount.header.frame_id = kBaseFrame;
  mount.child_frame_id = kImuFrame;
  mount.transform.translation.x = params.imu_position_m[0];
  mount.transform.translation.y = params.imu_position_m[1];
  mount.transform.translation.z = params.imu_position_m[2];
  const std::array<double, 4> q = SensorModel::quaternion(params.imu_mount_rpy_rad);
  mount.transform.rotation.x = q[0];
  mount.transform.rotation.y = q[1];
  mount.transform.rotation.z = q[2];
  mount.transform.rotation.w = q[3];
  bag->write(kTfStaticTopic, ros::Time(kDriveTimeOffset_s), tf);

  sensor_msgs::Imu imu;
  imu.header.frame_id = kImuFrame;
  imu.orientation_covariance[0] = -1.0;  // no orientation estimate
  const double var_f = std::pow(params.accel_noise_density, 2) * params.imu_rate_hz;
  const double var_w = std::pow(params.gyro_noise_density, 2) * params.imu_rate_hz;
  for (int j = 0; j < 3; ++j) {
    imu.linear_acceleration_covariance[4 * j] = var_f;
    imu.angular_velocity_covariance[4 * j] = var_w;
  }
  const std::size_t n_imu = sampleCount(drive, params.imu_rate_hz);
  for (std::size_t k = 0; k < n_imu; ++k) {
    const double t = t0 + static_cast<double>(k) / params.imu_rate_hz;
    const VehicleMotion motion = motionAt(t);
    vehicle.evaluate(motion, &state);
    // Yaw acceleration d(v kappa)/dt by a central difference over +-1 ms (the truth's curvature is piecewise
    // linear in distance).
    constexpr double kH = 1e-3;
    const VehicleMotion before = motionAt(t - kH), after = motionAt(t + kH);
    const double yaw_accel = (after.speed_mps * after.path_curvature_per_m -
                              before.speed_mps * before.path_curvature_per_m) / (2.0 * kH);
    const ImuReading r = sensors.imu(motion, state, yaw_accel);
    imu.header.stamp = ros::Time(t - t0 + kDriveTimeOffset_s);
    imu.linear_acceleration.x = r.specific_force_mps2[0];
    imu.linear_acceleration.y = r.specific_force_mps2[1];
    imu.linear_acceleration.z = r.specific_force_mps2[2];
    imu.angular_velocity.x = r.angular_rate_rps[0];
    imu.angular_velocity.y = r.angular_rate_rps[1];
    imu.angular_velocity.z = r.angular_rate_rps[2];
    bag->write(kImuTopic, imu.header.stamp, imu);
  }

  sensor_msgs::JointState joints;
  for (const char* name : kJointNames) joints.name.push_back(name);
  joints.position.assign(kWheelCount + 1, 0.0);
  joints.velocity.assign(kWheelCount + 1, 0.0);
  const std::size_t n_wheel = sampleCount(drive, params.wheel_rate_hz);
  const double dt_wheel = 1.0 / params.wheel_rate_hz;
  for (std::size_t k = 0; k < n_wheel; ++k) {
    const double t = t0 + static_cast<double>(k) * dt_wheel;
    vehicle.evaluate(motionAt(t), &state);
    const std::array<double, kWheelCount> omega = sensors.wheelSpeeds(state);
    joints.header.stamp = ros::Time(t - t0 + kDriveTimeOffset_s);
    for (int i = 0; i < kWheelCount; ++i) {
      if (k > 0) joints.position[i] += joints.velocity[i] * dt_wheel;  // wheel angle: integral of the signal
      joints.velocity[i] = omega[static_cast<std::size_t>(i)];
    }
    joints.position[kWheelCount] = sensors.steeringWheelAngle(state);
    bag->write(kJointStatesTopic, joints.header.stamp, joints);
  }

  nav_msgs::Odometry odom;
  odom.header.frame_id = kOdometryFrame;
  odom.child_frame_id = kBaseFrame;
  odom.pose.pose.orientation.w = 1.0;
  odom.twist.covariance[0] = params.odometry_noise_mps * params.odometry_noise_mps;
  const std::size_t n_odom = sampleCount(drive, params.odometry_rate_hz);
  for (std::size_t k = 0; k < n_odom; ++k) {
    const double t = t0 + static_cast<double>(k) / params.odometry_rate_hz;
    odom.header.stamp = ros::Time(t - t0 + kDriveTimeOffset_s);
    odom.twist.twist.linear.x = sensors.odometrySpeed(motionAt(t));
    bag->write(kOdometryTopic, ros::Time(t - t0 + kDriveTimeOffset_s + params.odometry_lag_s), odom);
  }
}

}  // namespace

WheelInputTopics wheelInputTopics(const std::string& name) {
  const std::string prefix = "/wheels/" + name + "/";
  return {prefix + "load", prefix + "slip", prefix + "speed", "wheel_" + name};
}

DriveStats writeDriveBag(const std::string& path, const DriveMotion& drive, const DriveDescription& description,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options) {
  if (!(options.rate_hz > 0.0) || options.wheel_names.size() != static_cast<std::size_t>(kWheelCount))
    throw BagError(path + ": drive needs rate_hz > 0 and 4 wheel names");
  std::string sensor_error;
  if (options.sensors && !options.sensor_params.validate(&sensor_error))
    throw BagError(path + ": sensor model: " + sensor_error);
  rosbag::Bag bag;
  openBagForWriting(&bag, path);
  std::vector<WheelInputTopics> topics;
  for (const std::string& name : options.wheel_names) topics.push_back(wheelInputTopics(name));
  DriveStats stats;
  const std::size_t n = sampleCount(drive, options.rate_hz);
  WheelLoad load;
  WheelSlip slip;
  WheelSpeed speed;
  VehicleState state;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = drive.startTime_s() + static_cast<double>(k) / options.rate_hz;
    const VehicleMotion motion = drive.at(t);
    vehicle.evaluate(motion, &state);
    stats.max_abs_lateral_accel_mps2 = std::max(stats.max_abs_lateral_accel_mps2, std::fabs(state.lateral_accel_mps2));
    stats.max_abs_accel_mps2 = std::max(stats.max_abs_accel_mps2, std::fabs(motion.accel_mps2));
    const ros::Time stamp(t - drive.startTime_s() + kDriveTimeOffset_s);
    for (int i = 0; i < kWheelCount; ++i) {
      const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
      load.header.stamp = slip.header.stamp = speed.header.stamp = stamp;
      load.header.frame_id = slip.header.frame_id = speed.header.frame_id = topics[i].frame;
      load.load_n = w.load_n;
      slip.slip_angle_rad = w.slip_angle_rad;
      slip.slip_ratio = w.slip_ratio;
      slip.path_curvature_per_m = w.path_curvature_per_m;
      speed.speed_mps = w.speed_mps;
      bag.write(topics[i].load, stamp, load);
      bag.write(topics[i].slip, stamp, slip);
      bag.write(topics[i].speed, stamp, speed);
    }
  }
  stats.samples = n;
  stats.duration_s = drive.duration_s();
  stats.distance_m = drive.distance_m();
  if (options.sensors) writeSensorTopics(&bag, drive, vehicle, options.sensor_params);

  DriveDescription described = description;
  described.duration_s = stats.duration_s;
  described.distance_m = stats.distance_m;
  std_msgs::String text;
  text.data = driveInfoJson(described, drive.route(), route_params, vehicle.params(),
                            {options.rate_hz, options.wheel_names, kDriveTimeOffset_s - drive.startTime_s(),
                             stats.max_abs_lateral_accel_mps2, stats.max_abs_accel_mps2});
  bag.write(kDriveInfoTopic, ros::Time(kDriveTimeOffset_s), text);
  bag.close();
  return stats;
}

DriveStats writeDriveBag(const std::string& path, const SpeedProfile& profile, const Route& route,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options) {
  return writeDriveBag(path, ProfileMotion(profile, route), {profile.name(), 0.0, 0.0, profile.phases(), {}}, vehicle,
                       route_params, options);
}

}  // namespace tread_wear
