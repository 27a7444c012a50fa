#pragma once
/// @file drive_bag_reader.h
/// A drive bag (drive_bag_writer.h, or a recording of the node's inputs) read into DriveReplay, with clear errors
/// for bad bags.

#include <string>
#include <vector>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/io/replay_summary_json.h"  // nlohmann::json, which only io and report include
#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/ros/bag/replay_config.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

/// What a drive bag holds besides the inputs.
struct DriveInfo {
  bool present = false;          ///< the bag has kDriveInfoTopic
  nlohmann::json json;           ///< its content
  std::vector<ProfilePhase> phases;  ///< drive phases (drive time)
  double time_offset_s = 0.0;    ///< bag time of drive time 0 [s]
};

/// Loads every input sample of the configured wheels into replay. Checks first that each wheel's load, slip
/// and speed topics exist with the right type (temperature is optional). @throw BagError
DriveInfo readDriveBag(const std::string& path, const ReplayConfig& config, DriveReplay* replay);

}  // namespace tread_wear
