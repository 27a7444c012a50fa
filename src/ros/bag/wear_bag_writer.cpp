#include "tread_wear/ros/bag/wear_bag_writer.h"

#include <rosbag/bag.h>

#include <algorithm>

#include "tread_wear/VehicleWear.h"
#include "tread_wear/WheelWear.h"

namespace tread_wear {

void writeWearBag(const std::string& path, const DriveReplay& replay, const ReplayConfig& config,
                  std::uint64_t decimation) {
  rosbag::Bag bag;
  openBagForWriting(&bag, path);
  const int n_wheels = replay.wheelCount();
  VehicleWear vehicle;
  vehicle.header.frame_id = "base_link";
  vehicle.wheels.resize(static_cast<std::size_t>(n_wheels));
  for (int w = 0; w < n_wheels; ++w) {
    WheelWear& m = vehicle.wheels[static_cast<std::size_t>(w)];
    m.header.frame_id = replay.wheel(w).frame_id;
    m.wheel = replay.wheel(w).name;
    m.tire_id = replay.wheel(w).tire_id;
  }
  const std::uint64_t step = std::max<std::uint64_t>(decimation, 1);
  for (std::uint64_t k = 0; k < replay.steps(); k += step) {
    const ros::Time stamp(replay.stepTime(k));
    vehicle.header.stamp = stamp;
    vehicle.total_wear_rate_kg_per_s = vehicle.total_wear_rate_kg_per_m = vehicle.total_accumulated_loss_kg = 0.0;
    for (int w = 0; w < n_wheels; ++w) {
      const StepRecord& r = replay.records(w)[k];
      WheelWear& m = vehicle.wheels[static_cast<std::size_t>(w)];
      m.header.stamp = stamp;
      m.wear_rate_kg_per_m = r.wear_rate_kg_per_m;
      m.wear_rate_kg_per_s = r.wear_rate_kg_per_s;
      m.accumulated_loss_kg = r.accumulated_loss_kg;
      m.tread_depth_loss_m = r.tread_depth_loss_m;
      m.remaining_tread_depth_m = r.remaining_tread_depth_m;
      m.distance_m = r.distance_m;
      m.stick_fraction = r.stick_fraction;
      m.slide_fraction = r.slide_fraction;
      m.exact_stick_fraction = r.exact_stick_fraction;
      m.fx_n = r.fx_n;
      m.fy_n = r.fy_n;
      m.mz_nm = r.mz_nm;
      m.preset = presetName(r.preset);
      m.degraded = r.preset != replay.settings().model.preset;
      m.status = static_cast<std::uint8_t>(r.status);
      m.unaccounted_time_s = r.unaccounted_time_s;
      vehicle.total_wear_rate_kg_per_s += m.wear_rate_kg_per_s;
      vehicle.total_wear_rate_kg_per_m += m.wear_rate_kg_per_m;
      vehicle.total_accumulated_loss_kg += m.accumulated_loss_kg;
      bag.write(config.wear_topics[static_cast<std::size_t>(w)], stamp, m);
    }
    bag.write("/wear", stamp, vehicle);
  }
  bag.close();
}

}  // namespace tread_wear
