#include "tread_wear/io/vehicle_params_io.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <map>
#include <stdexcept>

namespace tread_wear {

VehicleParams loadVehicleParams(const std::string& path) {
  auto failWith = [&](const std::string& what) -> void { throw std::runtime_error(path + ": " + what); };
  YAML::Node root;
  try {
    std::ifstream probe(path);
    if (!probe) failWith("cannot open the file for reading");
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    failWith(std::string("not a readable YAML document: ") + e.what());
  }
  if (!root.IsMap()) failWith("the document must be a mapping of vehicle parameters");
  VehicleParams p;
  const std::map<std::string, double*> numbers = {
      {"mass_kg", &p.mass_kg},
      {"wheelbase_m", &p.wheelbase_m},
      {"cog_to_front_axle_m", &p.cog_to_front_axle_m},
      {"cog_height_m", &p.cog_height_m},
      {"track_front_m", &p.track_front_m},
      {"track_rear_m", &p.track_rear_m},
      {"front_roll_stiffness_share", &p.front_roll_stiffness_share},
      {"all_wheel_front_drive_share", &p.all_wheel_front_drive_share},
      {"brake_balance_front", &p.brake_balance_front},
      {"ackermann_share", &p.ackermann_share},
      {"drag_coefficient", &p.drag_coefficient},
      {"frontal_area_m2", &p.frontal_area_m2},
      {"air_density_kg_per_m3", &p.air_density_kg_per_m3},
      {"rolling_resistance_coefficient", &p.rolling_resistance_coefficient},
      {"cornering_stiffness_front_per_rad", &p.cornering_stiffness_front_per_rad},
      {"cornering_stiffness_rear_per_rad", &p.cornering_stiffness_rear_per_rad},
      {"longitudinal_slip_stiffness", &p.longitudinal_slip_stiffness},
      {"gravity_mps2", &p.gravity_mps2}};
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    try {
      if (key == "format_version") {
        if (entry.second.as<int>() != 1) failWith("format_version " + entry.second.as<std::string>() + " is not 1");
      } else if (key == "name") {
        p.name = entry.second.as<std::string>();
      } else if (key == "drive_layout") {
        const std::string layout = entry.second.as<std::string>();
        if (!parseDriveLayout(layout, &p.drive_layout))
          failWith("drive_layout '" + layout + "' is not one of front, rear, all");
      } else {
        const auto it = numbers.find(key);
        if (it == numbers.end()) failWith("unknown key '" + key + "'");
        *it->second = entry.second.as<double>();
      }
    } catch (const YAML::Exception& e) {
      failWith("key '" + key + "': " + e.what());
    }
  }
  std::string error;
  if (!p.validate(&error)) failWith(error);
  return p;
}

}  // namespace tread_wear
