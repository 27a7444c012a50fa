#pragma once
/// @file drive_bag_writer.h
/// A generated test drive written as the node's input topics, and the drive bag's format (metadata topic, time
/// offset), which drive_bag_reader.h reads.

#include <cstddef>
#include <string>
#include <vector>

#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/vehicle/route.h"
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
};

/// Statistics of a written drive.
struct DriveStats {
  std::size_t samples = 0;        ///< time samples (each with all topics of all wheels) [-]
  double duration_s = 0.0;        ///< [s]
  double distance_m = 0.0;        ///< [m]
  double max_abs_lateral_accel_mps2 = 0.0;  ///< [m/s^2]
};

/// Writes the drive: for each of the 4 wheels load, slip and speed at rate_hz, header and record time = drive
/// time + kDriveTimeOffset_s, plus the metadata on kDriveInfoTopic. @throw BagError when the file cannot be written
DriveStats writeDriveBag(const std::string& path, const SpeedProfile& profile, const Route& route,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options);

}  // namespace tread_wear
