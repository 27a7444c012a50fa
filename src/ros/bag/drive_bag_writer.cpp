#include "tread_wear/ros/bag/drive_bag_writer.h"

#include <rosbag/bag.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/drive_info_json.h"

namespace tread_wear {

DriveStats writeDriveBag(const std::string& path, const SpeedProfile& profile, const Route& route,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options) {
  if (!(options.rate_hz > 0.0) || options.wheel_names.size() != static_cast<std::size_t>(kWheelCount))
    throw BagError(path + ": drive needs rate_hz > 0 and 4 wheel names");
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot write the bag: " + e.what());
  }
  std::vector<std::string> load_topics, slip_topics, speed_topics, frames;
  for (const std::string& name : options.wheel_names) {
    load_topics.push_back("/wheels/" + name + "/load");
    slip_topics.push_back("/wheels/" + name + "/slip");
    speed_topics.push_back("/wheels/" + name + "/speed");
    frames.push_back("wheel_" + name);
  }
  DriveStats stats;
  const std::size_t n = static_cast<std::size_t>(std::floor(profile.duration_s() * options.rate_hz + 1e-9)) + 1;
  WheelLoad load;
  WheelSlip slip;
  WheelSpeed speed;
  VehicleState state;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = profile.startTime_s() + static_cast<double>(k) / options.rate_hz;
    const VehicleMotion motion{profile.speed(t), profile.acceleration(t), route.curvature(profile.distance(t))};
    vehicle.evaluate(motion, &state);
    stats.max_abs_lateral_accel_mps2 = std::max(stats.max_abs_lateral_accel_mps2, std::fabs(state.lateral_accel_mps2));
    const ros::Time stamp(t - profile.startTime_s() + kDriveTimeOffset_s);
    for (int i = 0; i < kWheelCount; ++i) {
      const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
      load.header.stamp = slip.header.stamp = speed.header.stamp = stamp;
      load.header.frame_id = slip.header.frame_id = speed.header.frame_id = frames[i];
      load.load_n = w.load_n;
      slip.slip_angle_rad = w.slip_angle_rad;
      slip.slip_ratio = w.slip_ratio;
      slip.path_curvature_per_m = w.path_curvature_per_m;
      speed.speed_mps = w.speed_mps;
      bag.write(load_topics[i], stamp, load);
      bag.write(slip_topics[i], stamp, slip);
      bag.write(speed_topics[i], stamp, speed);
    }
  }
  stats.samples = n;
  stats.duration_s = profile.duration_s();
  stats.distance_m = profile.totalDistance_m();

  std_msgs::String text;
  text.data = driveInfoJson(profile, route, route_params, vehicle.params(),
                            {options.rate_hz, options.wheel_names, kDriveTimeOffset_s - profile.startTime_s(),
                             stats.max_abs_lateral_accel_mps2});
  bag.write(kDriveInfoTopic, ros::Time(kDriveTimeOffset_s), text);
  bag.close();
  return stats;
}

}  // namespace tread_wear
