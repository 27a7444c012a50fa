#include "tread_wear/ros/ros_log.h"

#include <ros/console.h>

namespace tread_wear {

LogSink rosconsoleSink() {
  return [](LogLevel level, const std::string& text) {
    switch (level) {
      case LogLevel::kDebug: ROS_DEBUG("%s", text.c_str()); break;
      case LogLevel::kInfo: ROS_INFO("%s", text.c_str()); break;
      case LogLevel::kWarn: ROS_WARN("%s", text.c_str()); break;
      case LogLevel::kError: ROS_ERROR("%s", text.c_str()); break;
    }
  };
}

}  // namespace tread_wear
