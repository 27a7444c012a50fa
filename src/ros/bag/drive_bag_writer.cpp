#include "tread_wear/ros/bag/drive_bag_writer.h"

#include <rosbag/bag.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/replay_summary_json.h"  // nlohmann::json, which only io and report include

namespace tread_wear {

namespace {

/// The vehicle parameters in the drive's metadata, so that a bag tells which car drove it.
nlohmann::json vehicleJson(const VehicleParams& p) {
  return {{"name", p.name},
          {"mass_kg", p.mass_kg},
          {"wheelbase_m", p.wheelbase_m},
          {"cog_to_front_axle_m", p.cog_to_front_axle_m},
          {"cog_height_m", p.cog_height_m},
          {"track_front_m", p.track_front_m},
          {"track_rear_m", p.track_rear_m},
          {"front_roll_stiffness_share", p.front_roll_stiffness_share},
          {"drive_layout", driveLayoutName(p.drive_layout)},
          {"all_wheel_front_drive_share", p.all_wheel_front_drive_share},
          {"brake_balance_front", p.brake_balance_front},
          {"drag_coefficient", p.drag_coefficient},
          {"frontal_area_m2", p.frontal_area_m2},
          {"air_density_kg_per_m3", p.air_density_kg_per_m3},
          {"rolling_resistance_coefficient", p.rolling_resistance_coefficient},
          {"cornering_stiffness_front_per_rad", p.cornering_stiffness_front_per_rad},
          {"cornering_stiffness_rear_per_rad", p.cornering_stiffness_rear_per_rad},
          {"longitudinal_slip_stiffness", p.longitudinal_slip_stiffness},
          {"gravity_mps2", p.gravity_mps2}};
}

}  // namespace

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

  nlohmann::json info;
  info["format"] = "tread_wear_drive";
  info["version"] = 1;
  info["profile"] = profile.name();
  info["rate_hz"] = options.rate_hz;
  info["time_offset_s"] = kDriveTimeOffset_s - profile.startTime_s();
  info["duration_s"] = stats.duration_s;
  info["distance_m"] = stats.distance_m;
  info["wheels"] = options.wheel_names;
  nlohmann::json phases = nlohmann::json::array();
  for (const ProfilePhase& p : profile.phases())
    phases.push_back({{"name", p.name}, {"start_s", p.start_s}, {"end_s", p.end_s}});
  info["phases"] = phases;
  info["vehicle"] = vehicleJson(vehicle.params());
  std::map<std::string, int> event_counts;
  for (const RouteEvent& e : route.events()) ++event_counts[routeEventKindName(e.kind)];
  info["route"] = {{"lateral_accel_limit_mps2", route_params.lateral_accel_limit_mps2},
                   {"seed", route_params.seed},
                   {"events", event_counts},
                   {"max_abs_lateral_accel_mps2", stats.max_abs_lateral_accel_mps2}};
  std_msgs::String text;
  text.data = info.dump(2);
  bag.write(kDriveInfoTopic, ros::Time(kDriveTimeOffset_s), text);
  bag.close();
  return stats;
}

}  // namespace tread_wear
