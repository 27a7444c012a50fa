#pragma once
/// @file wheel_pipeline.h
/// The ROS message side of a wheel's pipeline (pipeline/wheel_pipeline.h): the status code the wheel messages
/// carry and the wheel message filled from the last step. What a ROS 2 front end would write anew; the pipeline
/// itself it reuses.

#include <ros/time.h>

#include <cstdint>

#include "tread_wear/WheelWear.h"
#include "tread_wear/WheelWearRate.h"
#include "tread_wear/pipeline/wheel_pipeline.h"

namespace tread_wear {

/// The status code of WheelWear.status and WheelWearRate.status (one enumeration, the values of WheelStatus).
std::uint8_t statusCode(WheelStatus status);

/// Pre-sizes a wheel message's strings so that fillMessage() into it never allocates.
void reserveStrings(tread_wear::WheelWear* msg);

/// Loop side: the wheel's last step as a wheel message stamped `stamp` (in input time, with the step's own time
/// once there is one); degraded = coarser than `configured`. Allocates nothing in a message prepared by
/// reserveStrings().
void fillMessage(const WheelPipeline& wheel, const ros::Time& stamp, Preset configured, tread_wear::WheelWear* msg);

}  // namespace tread_wear
