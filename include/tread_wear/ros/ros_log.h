#pragma once
/// @file ros_log.h
/// The ROS 1 front end's log sink for the middleware-free parts (pipeline/node_persistence.h): rosconsole, at the
/// level the part gives.

#include "tread_wear/pipeline/node_persistence.h"

namespace tread_wear {

/// ROS_DEBUG / ROS_INFO / ROS_WARN / ROS_ERROR of the text, in the caller's thread.
LogSink rosconsoleSink();

}  // namespace tread_wear
