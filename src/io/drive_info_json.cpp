#include "tread_wear/io/drive_info_json.h"

#include <map>

#include <nlohmann/json.hpp>

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

/// The number under key of a phase; names the phase and the key when it is missing or not a number.
double phaseTime(const nlohmann::json& phase, std::size_t i, const char* key) {
  const auto it = phase.find(key);
  if (it == phase.end() || !it->is_number())
    throw DriveInfoError("phases[" + std::to_string(i) + "]." + key + " must be a number");
  return it->get<double>();
}

}  // namespace

std::string driveInfoJson(const DriveDescription& drive, const Route& route, const RouteParams& route_params,
                          const VehicleParams& vehicle, const DriveSampling& sampling) {
  nlohmann::json info;
  info["format"] = "tread_wear_drive";
  info["version"] = 1;
  info["profile"] = drive.name;
  info["rate_hz"] = sampling.rate_hz;
  info["time_offset_s"] = sampling.time_offset_s;
  info["duration_s"] = drive.duration_s;
  info["distance_m"] = drive.distance_m;
  info["wheels"] = sampling.wheel_names;
  nlohmann::json phases = nlohmann::json::array();
  for (const ProfilePhase& p : drive.phases)
    phases.push_back({{"name", p.name}, {"start_s", p.start_s}, {"end_s", p.end_s}});
  info["phases"] = phases;
  info["vehicle"] = vehicleJson(vehicle);
  std::map<std::string, int> event_counts;
  for (const RouteEvent& e : route.events()) ++event_counts[routeEventKindName(e.kind)];
  info["route"] = {{"lateral_accel_limit_mps2", route_params.lateral_accel_limit_mps2},
                   {"seed", route_params.seed},
                   {"events", event_counts},
                   {"max_abs_lateral_accel_mps2", sampling.max_abs_lateral_accel_mps2}};
  if (drive.scenario) {
    nlohmann::json settings = nlohmann::json::object();
    for (const auto& [key, value] : drive.scenario->settings) settings[key] = value;
    nlohmann::json scenario = {{"manoeuvre", drive.scenario->manoeuvre},
                               {"settings", settings},
                               {"duration_s", drive.duration_s},
                               {"distance_m", drive.distance_m},
                               {"max_abs_accel_mps2", sampling.max_abs_accel_mps2},
                               {"max_abs_lateral_accel_mps2", sampling.max_abs_lateral_accel_mps2}};
    if (!drive.scenario->style.empty()) scenario["style"] = drive.scenario->style;
    info["scenario"] = scenario;
  }
  return info.dump(2);
}

DriveMetadata parseDriveInfo(const std::string& text) {
  nlohmann::json info;
  try {
    info = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw DriveInfoError(std::string("not JSON: ") + e.what());
  }
  if (!info.is_object()) throw DriveInfoError("not a JSON object but a " + std::string(info.type_name()));
  DriveMetadata metadata;
  metadata.text = text;
  if (const auto offset = info.find("time_offset_s"); offset != info.end()) {
    if (!offset->is_number()) throw DriveInfoError("time_offset_s must be a number");
    metadata.time_offset_s = offset->get<double>();
  }
  if (const auto phases = info.find("phases"); phases != info.end()) {
    if (!phases->is_array()) throw DriveInfoError("phases must be a list");
    for (std::size_t i = 0; i < phases->size(); ++i) {
      const nlohmann::json& p = (*phases)[i];
      if (!p.is_object()) throw DriveInfoError("phases[" + std::to_string(i) + "] must be a map");
      const auto name = p.find("name");
      if (name == p.end() || !name->is_string())
        throw DriveInfoError("phases[" + std::to_string(i) + "].name must be a string");
      metadata.phases.push_back({name->get<std::string>(), phaseTime(p, i, "start_s"), phaseTime(p, i, "end_s")});
    }
  }
  return metadata;
}

}  // namespace tread_wear
