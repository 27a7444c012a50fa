#pragma once
/// @file wear_bag_writer.h
/// The wear topics of a finished replay (DriveReplay) written to a bag, as the node would have published them.

#include <cstdint>
#include <string>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/ros/bag/replay_config.h"

namespace tread_wear {

/// Writes WheelWear per wheel (on config.wear_topics) and VehicleWear on /wear for every `decimation`-th
/// step, stamped with the step time. @throw BagError
void writeWearBag(const std::string& path, const DriveReplay& replay, const ReplayConfig& config,
                  std::uint64_t decimation);

}  // namespace tread_wear
