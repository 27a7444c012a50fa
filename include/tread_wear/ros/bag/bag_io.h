#pragma once
/// @file bag_io.h
/// rosbag side of the test drives: writing a generated drive as the node's input topics, reading a drive bag
/// into DriveReplay (with clear errors for bad bags) and writing the replay's wear topics; the replay's
/// configuration is in replay_config.h.

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/ros/bag/replay_config.h"
#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

/// A bag that cannot be replayed: missing or unreadable file, corrupt or truncated data, missing topics,
/// wrong message types. what() names the file and the problem.
class BagError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Topic of the drive's metadata (std_msgs/String, JSON: profile, phases, vehicle, route, time offset).
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

/// What a drive bag holds besides the inputs.
struct DriveInfo {
  bool present = false;          ///< the bag has kDriveInfoTopic
  nlohmann::json json;           ///< its content
  std::vector<ProfilePhase> phases;  ///< drive phases (drive time)
  double time_offset_s = 0.0;    ///< bag time of drive time 0 [s]
};

/// Checks the records of a rosbag 2.0 file before rosbag reads it, since rosbag and ros::Header::parse read
/// lengths from the file without bounds checks (a corrupt one makes them read past their buffers, or crash): every
/// record and header field must lie within the file, every record of every chunk within its chunk (bz2 and lz4
/// chunks are decompressed first, to exactly their size field, at most 1 GiB), and every index entry must point at
/// a record of its chunk that leads to a message. Chunks of another compression are left to rosbag, as are other
/// bag versions. Reads the file once, a record at a time (memory: one chunk, and its decompressed data).
/// @throw BagError naming the file, the problem and its byte offset
void checkBagRecords(const std::string& path);

/// Loads every input sample of the configured wheels into replay. Checks first that each wheel's load, slip
/// and speed topics exist with the right type (temperature is optional). @throw BagError
DriveInfo readDriveBag(const std::string& path, const ReplayConfig& config, DriveReplay* replay);

/// Writes WheelWear per wheel (on config.wear_topics) and VehicleWear on /wear for every `decimation`-th
/// step, stamped with the step time. @throw BagError
void writeWearBag(const std::string& path, const DriveReplay& replay, const ReplayConfig& config,
                  std::uint64_t decimation);

}  // namespace tread_wear
