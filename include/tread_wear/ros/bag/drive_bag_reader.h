#pragma once
/// @file drive_bag_reader.h
/// A drive bag (drive_bag_writer.h, or a recording of the node's inputs) read into DriveReplay, with clear errors
/// for bad bags.

#include <string>
#include <vector>

#include <rosbag/message_instance.h>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/io/drive_info_json.h"
#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/ros/bag/replay_config.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

/// What a drive bag holds besides the inputs: its metadata (io/drive_info_json.h), if it has any.
struct DriveInfo : DriveMetadata {
  bool present = false;  ///< the bag has kDriveInfoTopic; otherwise no phases, offset 0, empty text
};

/// Loads every input sample of the configured wheels into replay. Checks first that each wheel's load, slip
/// and speed topics exist with the right type (temperature is optional). Of several metadata messages the last
/// counts. @throw BagError, also for metadata that cannot be read (naming the problem)
/// The input sample a message of an input topic holds (its kind from the topic), at the message's record time.
/// @throw ros::Exception when the message does not decode as that kind's type
InputSample inputSample(const rosbag::MessageInstance& message, InputKind kind);

DriveInfo readDriveBag(const std::string& path, const ReplayConfig& config, DriveReplay* replay);

}  // namespace tread_wear
