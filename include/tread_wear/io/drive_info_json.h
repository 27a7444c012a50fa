#pragma once
/// @file drive_info_json.h
/// The drive metadata a drive bag carries beside its input topics (ros/bag/drive_bag_writer.h): a JSON document
/// with the profile, its phases, the vehicle, the route and the time offset, written by tread_wear_drive and read
/// back by tread_wear_replay, which takes the phases and the offset and embeds the whole document in its summary
/// (docs/drive.md). Here, so that the bag tools never touch the JSON library.

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

/// Drive metadata that cannot be used: names the key or the phase and what is wrong with it.
class DriveInfoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a drive was sampled into a bag, beside what the profile, route and vehicle say.
struct DriveSampling {
  double rate_hz = 0.0;                      ///< sample rate of every input topic [Hz]
  std::vector<std::string> wheel_names;      ///< in vehicle wheel order
  double time_offset_s = 0.0;                ///< bag time of the profile's time 0 [s]
  double max_abs_lateral_accel_mps2 = 0.0;   ///< largest |a_y| over the written samples [m/s^2]
  double max_abs_accel_mps2 = 0.0;           ///< largest |a_x| over the written samples [m/s^2]
};

/// What made a drive other than a cycle driven as it prescribes: a manoeuvre (vehicle/manoeuvre.h) or the cycle's
/// route driven within a driving style's envelope (vehicle/driving_style.h).
struct DriveScenarioInfo {
  std::string manoeuvre;  ///< "cruise", "circle", "accel" or "profile" (a style's drive of the profile)
  std::string style;      ///< the style's name for a style's drive, else empty
  /// The settings, SI with the unit in the key (speed_mps, max_accel_mps2, ...), in this order.
  std::vector<std::pair<std::string, double>> settings;
};

/// The drive as a whole: name, extent, phases, and its scenario when it is not the cycle as prescribed.
struct DriveDescription {
  std::string name;                          ///< profile or manoeuvre name
  double duration_s = 0.0;                   ///< [s]
  double distance_m = 0.0;                   ///< [m]
  std::vector<ProfilePhase> phases;          ///< drive time [s]
  std::optional<DriveScenarioInfo> scenario;
};

/// The metadata as read back: what the replay uses, and the document itself to pass on.
struct DriveMetadata {
  std::string text;                  ///< the JSON document as it was read
  std::vector<ProfilePhase> phases;  ///< drive phases (profile time) [s]
  double time_offset_s = 0.0;        ///< bag time of profile time 0 [s]; 0 when the document has none
};

/// The metadata document (format "tread_wear_drive", version 1), indented JSON: profile (the drive's name), rate,
/// time offset, duration, distance, wheels, phases, vehicle parameters, route parameters and event counts, and for a
/// scenario "scenario": {manoeuvre, style (when set), settings {...}, duration_s, distance_m, max_abs_accel_mps2,
/// max_abs_lateral_accel_mps2}, the figures measured over the written samples.
std::string driveInfoJson(const DriveDescription& drive, const Route& route, const RouteParams& route_params,
                          const VehicleParams& vehicle, const DriveSampling& sampling);

/// Reads the phases and the time offset of a metadata document (both optional; other keys are passed on
/// unread). @throw DriveInfoError when the text is not a JSON object, time_offset_s is not a number, phases is
/// not a list, or a phase lacks a string name or a numeric start_s or end_s
DriveMetadata parseDriveInfo(const std::string& text);

}  // namespace tread_wear
