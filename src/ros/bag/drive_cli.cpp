#include "tread_wear/ros/bag/drive_cli.h"

#include <ros/time.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <utility>
#include <vector>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/driving_programme_csv.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/vehicle/driving_programme.h"
#include "tread_wear/vehicle/driving_style.h"
#include "tread_wear/vehicle/manoeuvre.h"

namespace tread_wear {
namespace {

const char* const kUsage =
    "usage: tread_wear_drive [--manoeuvre profile|cruise|circle|accel] [manoeuvre options]\n"
    "                        [--style calm|normal|aggressive] [--max-accel-mps2 A] [--max-decel-mps2 D]\n"
    "                        [--max-lateral-accel-mps2 AY]\n"
    "                        [--profile SPEED.csv] [--vehicle VEHICLE.yaml] [--mass-kg M] [--drive-layout L]\n"
    "                        [--rate-hz 50] [--lateral-accel-limit 3.0] [--seed N] [--sensors] --out DRIVE.bag\n"
    "       tread_wear_drive --programme DIR --section ID [--turns TURNS.csv] [--laps N] [--mirror]\n"
    "                        [--corner-lateral-accel-mps2 4] [--slow-for-corners] [--corner-brake-mps2 2.94]\n"
    "                        [--corner-accel-mps2 1] [--steer-transition-s 1] [--smoothing-s 1]\n"
    "                        [--vehicle VEHICLE.yaml] [--mass-kg M] [--drive-layout L] [--rate-hz 50] --out DRIVE.bag\n"
    "                        (vehicle default: config/vehicle_ford_kuga.yaml, the programme's car)\n"
    "  --manoeuvre  profile: the speed profile over its route (default); cruise: constant speed on a straight;\n"
    "               circle: steady cornering; accel: accelerate/brake cycles on a straight (docs/drive.md)\n"
    "    cruise, circle: --speed-kmh V [km/h] --duration-s T [s], started at steady state\n"
    "    circle:         --lateral-accel A [m/s^2] (radius V^2/A, <= 8) [--direction left|right]\n"
    "    accel:          --low-speed-kmh V1 --high-speed-kmh V2 [km/h] --accel-mps2 A --decel-mps2 D [m/s^2, > 0]\n"
    "                    --duration-s T: from V1, accelerate at A to V2, brake at D to V1, repeated\n"
    "  --style calm|normal|aggressive  drive the profile's route and stops within the style's envelope:\n"
    "               a_max/d_max/a_y,max 1.0/1.5/2.0, 1.7/2.5/3.0, 3.0/4.0/4.5 m/s^2 (docs/drive.md)\n"
    "  --max-accel-mps2 A  --max-decel-mps2 D  --max-lateral-accel-mps2 AY  the envelope's values instead of the\n"
    "               style's (style normal when only these are given) [m/s^2, > 0, <= 8]\n"
    "  --profile    speed profile CSV (time_s, speed_kmh or speed_mps) [default: data/wltc_class3b.csv]\n"
    "  --vehicle    vehicle parameters [default: config/vehicle_passenger_car.yaml]\n"
    "  --mass-kg    vehicle mass instead of the file's [kg]; static loads follow, CoG position kept\n"
    "  --drive-layout  front|rear|all instead of the file's\n"
    "  --rate-hz    sample rate of every input topic [Hz]\n"
    "  --lateral-accel-limit  a_y limit that sets the profile route's curve radii [m/s^2]\n"
    "  --seed       route random stream (deterministic per seed)\n"
    "  --sensors    also write what the car's sensors measured on the same drive: imu, joint_states, odom,\n"
    "               /tf_static (sensor model and its fixed parameters: docs/vehicle_inputs.md)\n"
    "  --programme  a proving-ground programme's test section (vehicle/driving_programme.h; "
    "docs/measured_road_wear.md):\n"
    "               DIR with sectors.csv, maneuvers.csv, test_sections.csv (the package's: data/leon_t_idiada)\n"
    "    --section  its Test section (Run-in, Rural_60_kph, Motorway, Urban_pa_30kph, ...)\n"
    "    --turns    each corner's direction [default: DIR/turns.csv]; --mirror drives every corner the other way\n"
    "    --laps     laps instead of the programme's (the laps are alike: per-km results need only a few)\n"
    "    --corner-lateral-accel-mps2  the driver's bound on v^2 kappa: corners widened to reach it [m/s^2]\n"
    "    --slow-for-corners  keep each corner's radius and slow to the bound instead, braking before it at\n"
    "               --corner-brake-mps2 and accelerating after it at --corner-accel-mps2 [m/s^2]\n"
    "    --steer-transition-s  clothoid length into and out of a corner = v x this [s]\n"
    "    --smoothing-s  speed-step smoothing window [s]\n";

/// A params struct's validate() error ("<field> = <value>: must be ...") as the command line's error, naming the
/// option the field came from when `options` (field, option) has it. Always false.
template <std::size_t N>
bool failInOption(const std::string& field_error, const std::pair<const char*, const char*> (&options)[N],
                  std::string* error) {
  for (const auto& [field, option] : options) {
    if (field_error.rfind(std::string(field) + " =", 0) == 0) {
      *error = std::string(option) + " out of range: " + field_error;
      return false;
    }
  }
  *error = field_error;
  return false;
}

/// The command-line option of each ManoeuvreParams field, so that a validation error names what the user typed.
const std::pair<const char*, const char*> kManoeuvreOptions[] = {
    {"speed_mps", "--speed-kmh"},         {"lateral_accel_mps2", "--lateral-accel"}, {"duration_s", "--duration-s"},
    {"low_speed_mps", "--low-speed-kmh"}, {"high_speed_mps", "--high-speed-kmh"},    {"accel_mps2", "--accel-mps2"},
    {"decel_mps2", "--decel-mps2"}};

/// The options each manoeuvre takes (all required); any other manoeuvre option is a usage error.
std::vector<std::string> manoeuvreOptions(Manoeuvre kind) {
  switch (kind) {
    case Manoeuvre::kProfile:
      return {};
    case Manoeuvre::kCruise:
      return {"speed-kmh", "duration-s"};
    case Manoeuvre::kCircle:
      return {"speed-kmh", "lateral-accel", "duration-s"};
    case Manoeuvre::kAccelCycles:
      return {"low-speed-kmh", "high-speed-kmh", "accel-mps2", "decel-mps2", "duration-s"};
  }
  return {};
}

/// Reads the manoeuvre's options into params (km/h to m/s); false with a message naming the option.
bool readManoeuvre(const CommandLine& args, ManoeuvreParams* params, std::string* error) {
  const std::string name = args.get("manoeuvre", "profile");
  if (!parseManoeuvre(name, &params->kind)) {
    *error = "--manoeuvre must be profile, cruise, circle or accel, not '" + name + "'";
    return false;
  }
  // The profile's and its route's options do not shape a manoeuvre: refused rather than ignored.
  for (const char* option : {"profile", "lateral-accel-limit", "seed"}) {
    if (params->kind != Manoeuvre::kProfile && args.has(option)) {
      *error = std::string("--") + option + " is not an option of --manoeuvre " + name;
      return false;
    }
  }
  const std::vector<std::string> wanted = manoeuvreOptions(params->kind);
  for (const char* option : {"speed-kmh", "lateral-accel", "direction", "duration-s", "low-speed-kmh", "high-speed-kmh",
                             "accel-mps2", "decel-mps2"}) {
    const bool used = std::find(wanted.begin(), wanted.end(), option) != wanted.end() ||
                      (params->kind == Manoeuvre::kCircle && std::string(option) == "direction");
    if (args.has(option) && !used) {
      *error = std::string("--") + option + " is not an option of --manoeuvre " + name;
      return false;
    }
  }
  for (const std::string& option : wanted) {
    if (!args.has(option)) {
      *error = "--manoeuvre " + name + " needs --" + option;
      return false;
    }
  }
  double speed_kmh = params->speed_mps * 3.6, low_kmh = params->low_speed_mps * 3.6,
         high_kmh = params->high_speed_mps * 3.6;
  if (!args.number("speed-kmh", &speed_kmh, error) ||
      !args.number("lateral-accel", &params->lateral_accel_mps2, error) ||
      !args.number("duration-s", &params->duration_s, error) || !args.number("low-speed-kmh", &low_kmh, error) ||
      !args.number("high-speed-kmh", &high_kmh, error) || !args.number("accel-mps2", &params->accel_mps2, error) ||
      !args.number("decel-mps2", &params->decel_mps2, error))
    return false;
  params->speed_mps = speed_kmh / 3.6;
  params->low_speed_mps = low_kmh / 3.6;
  params->high_speed_mps = high_kmh / 3.6;
  const std::string direction = args.get("direction", "left");
  if (direction != "left" && direction != "right") {
    *error = "--direction must be left or right, not '" + direction + "'";
    return false;
  }
  params->turn_right = direction == "right";
  std::string field_error;
  return params->validate(&field_error) || failInOption(field_error, kManoeuvreOptions, error);
}

/// The command-line option of each DrivingEnvelope field.
const std::pair<const char*, const char*> kEnvelopeOptions[] = {{"max_accel_mps2", "--max-accel-mps2"},
                                                                {"max_decel_mps2", "--max-decel-mps2"},
                                                                {"max_lateral_accel_mps2", "--max-lateral-accel-mps2"}};

/// Reads --style and the envelope options; *style is empty when none of them is given (the profile as it
/// prescribes). False with a message naming the option.
bool readEnvelope(const CommandLine& args, bool profile_drive, std::string* style, DrivingEnvelope* envelope,
                  std::string* error) {
  style->clear();
  bool any = false;
  for (const char* option : {"style", "max-accel-mps2", "max-decel-mps2", "max-lateral-accel-mps2"}) {
    if (!args.has(option)) continue;
    if (!profile_drive) {
      *error = std::string("--") + option + " is not an option of --manoeuvre " + args.get("manoeuvre");
      return false;
    }
    any = true;
  }
  if (!any) return true;
  *style = args.get("style", "normal");
  if (!drivingStyle(*style, envelope)) {
    *error = "--style must be calm, normal or aggressive, not '" + *style + "'";
    return false;
  }
  if (!args.number("max-accel-mps2", &envelope->max_accel_mps2, error) ||
      !args.number("max-decel-mps2", &envelope->max_decel_mps2, error) ||
      !args.number("max-lateral-accel-mps2", &envelope->max_lateral_accel_mps2, error))
    return false;
  std::string field_error;
  return envelope->validate(&field_error) || failInOption(field_error, kEnvelopeOptions, error);
}

/// The vehicle file's parameters with the command line's mass and drive layout; false with a message naming the
/// option. The CoG position (l_f) is kept, so the static loads scale with the mass.
bool overrideVehicle(const CommandLine& args, VehicleParams* vehicle, std::string* error) {
  if (!args.number("mass-kg", &vehicle->mass_kg, error)) return false;
  if (args.has("drive-layout") && !parseDriveLayout(args.get("drive-layout"), &vehicle->drive_layout)) {
    *error = "--drive-layout must be front, rear or all, not '" + args.get("drive-layout") + "'";
    return false;
  }
  std::string field_error;
  if (!vehicle->validate(&field_error)) {
    *error = (args.has("mass-kg") && field_error.rfind("mass_kg =", 0) == 0 ? "--mass-kg out of range: "
                                                                            : "vehicle parameters: ") +
             field_error;
    return false;
  }
  return true;
}

/// The programme options into the section and the builder's params; false with a message naming the option.
bool readProgramme(const CommandLine& args, const DrivingProgramme& programme, ProgrammeSection* section,
                   ProgrammeDriveParams* params, std::string* error) {
  if (!args.has("section")) {
    *error = "--programme needs --section (one of test_sections.csv's Test section)";
    return false;
  }
  const ProgrammeSection* found = programme.section(args.get("section"));
  if (found == nullptr) {
    *error = "--section '" + args.get("section") + "' is not a test section of the programme";
    return false;
  }
  *section = *found;
  if (!args.integer("laps", &section->laps, error) ||
      !args.number("corner-lateral-accel-mps2", &params->max_lateral_accel_mps2, error) ||
      !args.number("steer-transition-s", &params->steer_transition_s, error) ||
      !args.number("smoothing-s", &params->smoothing_s, error) ||
      !args.number("corner-brake-mps2", &params->corner_brake_mps2, error) ||
      !args.number("corner-accel-mps2", &params->corner_accel_mps2, error))
    return false;
  if (section->laps < 1) {
    *error = "--laps must be >= 1";
    return false;
  }
  params->mirror = args.has("mirror");
  params->slow_for_corners = args.has("slow-for-corners");
  const std::pair<const char*, const char*> options[] = {{"max_lateral_accel_mps2", "--corner-lateral-accel-mps2"},
                                                         {"steer_transition_s", "--steer-transition-s"},
                                                         {"smoothing_s", "--smoothing-s"},
                                                         {"corner_brake_mps2", "--corner-brake-mps2"},
                                                         {"corner_accel_mps2", "--corner-accel-mps2"}};
  std::string field_error;
  return params->validate(&field_error) || failInOption(field_error, options, error);
}

/// The value options of each kind of drive: the profile's, the manoeuvres' and the styles' (refused with
/// --programme rather than ignored), the programme's (refused without it), and those of every drive.
const std::vector<std::string> kProfileAndManoeuvreOptions = {
    "profile",        "lateral-accel-limit",    "seed",       "manoeuvre",     "style",     "max-accel-mps2",
    "max-decel-mps2", "max-lateral-accel-mps2", "speed-kmh",  "lateral-accel", "direction", "duration-s",
    "low-speed-kmh",  "high-speed-kmh",         "accel-mps2", "decel-mps2"};
const std::vector<std::string> kProgrammeOptions = {
    "programme",          "section",           "turns",      "laps", "corner-lateral-accel-mps2", "steer-transition-s",
    "smoothing-s",        "corner-brake-mps2", "corner-accel-mps2"};
const std::vector<std::string> kCommonOptions = {"vehicle", "out", "rate-hz", "mass-kg", "drive-layout"};

/// tread_wear_drive --programme: one test section as a drive bag, with its statistics on out.
int runProgrammeDrive(const CommandLine& args, const std::string& share_dir, DriveOptions options, std::ostream& out,
                      std::ostream& err) {
  auto usage_error = [&err](const std::string& message) {
    return usageError(err, "tread_wear_drive", message, kUsage);
  };
  for (const std::string& option : kProfileAndManoeuvreOptions)
    if (args.has(option)) return usage_error("--" + option + " is not an option of --programme");
  if (args.has("sensors")) return usage_error("--sensors is not an option of --programme");
  const std::string dir = args.get("programme");
  const std::string turns = args.get("turns", dir + "/turns.csv");
  std::string error;
  try {
    const DrivingProgramme programme = readDrivingProgramme(dir, turns);
    ProgrammeSection section;
    ProgrammeDriveParams params;
    if (!readProgramme(args, programme, &section, &params, &error)) return usage_error(error);
    VehicleParams vehicle_params = loadVehicleParams(args.get("vehicle", share_dir + "/config/vehicle_ford_kuga.yaml"));
    if (!overrideVehicle(args, &vehicle_params, &error)) return usage_error(error);
    const ProgrammeDrive drive = buildProgrammeDrive(programme, section, params);
    ros::Time::init();
    for (int w = 0; w < kWheelCount; ++w) options.wheel_names.push_back(wheelName(w));
    const DriveScenarioInfo scenario{"programme",
                                     "",
                                     {{"laps", section.laps},
                                      {"lap_length_m", drive.lap_length_m},
                                      {"corner_lateral_accel_mps2", params.max_lateral_accel_mps2},
                                      {"steer_transition_s", params.steer_transition_s},
                                      {"smoothing_s", params.smoothing_s},
                                      {"mirror", params.mirror ? 1.0 : 0.0},
                                      {"slow_for_corners", params.slow_for_corners ? 1.0 : 0.0},
                                      {"corner_brake_mps2", params.corner_brake_mps2},
                                      {"corner_accel_mps2", params.corner_accel_mps2}}};
    const DriveStats stats = writeDriveBag(args.get("out"), drive.motion, {section.id, 0.0, 0.0, {}, scenario},
                                           VehicleModel(vehicle_params), RouteParams{}, options);
    out << formatted(
        "%s: %s (%s, %s), %d laps of %.1f m, %.0f s, %.3f km, %zu samples x 4 wheels at %g Hz, "
        "max |a_x| %.2f m/s^2, max |a_y| %.2f m/s^2\n",
        args.get("out").c_str(), section.id.c_str(), section.test.c_str(), section.track.c_str(), section.laps,
        drive.lap_length_m, stats.duration_s, stats.distance_m / 1000.0, stats.samples, options.rate_hz,
        stats.max_abs_accel_mps2, stats.max_abs_lateral_accel_mps2);
    out << formatted("  corner bound %g m/s^2 (%s): %d corners widened per lap; manoeuvre distance beyond the laps: "
                     "%.1f m\n",
                     params.max_lateral_accel_mps2, params.slow_for_corners ? "slowed to" : "widened to",
                     drive.widened_corners, drive.unabsorbed_m);
    out << formatted("  vehicle: %s, %.0f kg, %s-wheel drive\n", vehicle_params.name.c_str(), vehicle_params.mass_kg,
                     driveLayoutName(vehicle_params.drive_layout));
  } catch (const std::exception& e) {
    err << "tread_wear_drive: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace

int runDriveCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out,
                std::ostream& err) {
  DriveOptions options;
  RouteParams route_params;
  auto usage_error = [&err](const std::string& message) {
    return usageError(err, "tread_wear_drive", message, kUsage);
  };
  CommandLine args;
  std::string error;
  std::vector<std::string> value_options = kCommonOptions;
  for (const auto* kind : {&kProfileAndManoeuvreOptions, &kProgrammeOptions})
    value_options.insert(value_options.end(), kind->begin(), kind->end());
  if (!args.parse(argc, argv, value_options, {"sensors", "mirror", "slow-for-corners"}, &error)) return usage_error(error);
  if (args.help()) {
    out << kUsage;
    return 0;
  }
  int seed = static_cast<int>(route_params.seed);
  if (!args.number("rate-hz", &options.rate_hz, &error) ||
      !args.number("lateral-accel-limit", &route_params.lateral_accel_limit_mps2, &error) ||
      !args.integer("seed", &seed, &error))
    return usage_error(error);
  if (!args.has("out")) return usage_error("--out is required");
  if (!(options.rate_hz > 0.0)) return usage_error("--rate-hz must be > 0");
  if (seed < 0) return usage_error("--seed must be >= 0");
  route_params.seed = static_cast<std::uint32_t>(seed);
  if (args.has("programme")) return runProgrammeDrive(args, share_dir, options, out, err);
  for (const std::string& option : kProgrammeOptions)
    if (args.has(option)) return usage_error("--" + option + " is an option of --programme only");
  for (const char* flag : {"mirror", "slow-for-corners"})
    if (args.has(flag)) return usage_error(std::string("--") + flag + " is an option of --programme only");
  ManoeuvreParams manoeuvre;
  if (!readManoeuvre(args, &manoeuvre, &error)) return usage_error(error);
  std::string style;
  DrivingEnvelope envelope;
  if (!readEnvelope(args, manoeuvre.kind == Manoeuvre::kProfile, &style, &envelope, &error)) return usage_error(error);
  options.sensors = args.has("sensors");
  const std::string profile_path = args.get("profile", share_dir + "/data/wltc_class3b.csv");
  const std::string vehicle_path = args.get("vehicle", share_dir + "/config/vehicle_passenger_car.yaml");
  const std::string bag_path = args.get("out");
  try {
    ros::Time::init();
    VehicleParams vehicle_params = loadVehicleParams(vehicle_path);
    if (!overrideVehicle(args, &vehicle_params, &error)) return usage_error(error);
    const VehicleModel vehicle(vehicle_params);
    for (int w = 0; w < kWheelCount; ++w) options.wheel_names.push_back(wheelName(w));
    std::string name;
    DriveStats stats;
    std::size_t curve_events = 0;
    if (manoeuvre.kind == Manoeuvre::kProfile) {
      const SpeedProfile profile = loadSpeedProfile(profile_path);
      const Route route = buildRoute(profile, route_params);
      name = profile.name();
      curve_events = route.events().size();
      if (style.empty()) {
        stats = writeDriveBag(bag_path, profile, route, vehicle, route_params, options);
      } else {
        const EnvelopeDriveParams drive_params;
        const EnvelopeDrive drive = driveWithinEnvelope(profile, route, envelope, drive_params);
        const DriveScenarioInfo scenario{"profile",
                                         style,
                                         {{"max_accel_mps2", envelope.max_accel_mps2},
                                          {"max_decel_mps2", envelope.max_decel_mps2},
                                          {"max_lateral_accel_mps2", envelope.max_lateral_accel_mps2},
                                          {"target_window_m", drive_params.target_window_m},
                                          {"smoothing_s", drive_params.smoothing_s}}};
        stats = writeDriveBag(bag_path, drive.trace, {name, 0.0, 0.0, drive.phases, scenario}, vehicle, route_params,
                              options);
      }
    } else {
      const SpeedTrace trace = buildManoeuvre(manoeuvre);
      name = manoeuvreName(manoeuvre.kind);
      DriveScenarioInfo scenario{name, "", {}};
      if (manoeuvre.kind == Manoeuvre::kAccelCycles) {
        scenario.settings = {{"low_speed_mps", manoeuvre.low_speed_mps},
                             {"high_speed_mps", manoeuvre.high_speed_mps},
                             {"accel_mps2", manoeuvre.accel_mps2},
                             {"decel_mps2", manoeuvre.decel_mps2},
                             {"smoothing_s", trace.smoothing_s()}};
      } else {
        scenario.settings = {{"speed_mps", manoeuvre.speed_mps}};
        if (manoeuvre.kind == Manoeuvre::kCircle) {
          scenario.settings.push_back({"lateral_accel_mps2", manoeuvre.lateral_accel_mps2});
          scenario.settings.push_back({"radius_m", manoeuvre.circleRadius_m()});
          scenario.settings.push_back({"curvature_per_m", trace.route().curvature(0.0)});  // > 0 left
        }
      }
      stats = writeDriveBag(bag_path, trace, {name, 0.0, 0.0, {}, scenario}, vehicle, route_params, options);
    }
    out << formatted(
        "%s: %s, %.0f s, %.2f km, %zu samples x 4 wheels at %g Hz, "
        "%zu curve events, max |a_x| %.2f m/s^2, max |a_y| %.2f m/s^2\n",
        bag_path.c_str(), name.c_str(), stats.duration_s, stats.distance_m / 1000.0, stats.samples, options.rate_hz,
        curve_events, stats.max_abs_accel_mps2, stats.max_abs_lateral_accel_mps2);
    out << formatted("  vehicle: %s, %.0f kg, %s-wheel drive\n", vehicle_params.name.c_str(), vehicle_params.mass_kg,
                     driveLayoutName(vehicle_params.drive_layout));
    if (!style.empty())
      out << formatted("  style %s: a_max %g, d_max %g, a_y,max %g m/s^2\n", style.c_str(), envelope.max_accel_mps2,
                       envelope.max_decel_mps2, envelope.max_lateral_accel_mps2);
    if (options.sensors) {
      const SensorModelParams& s = options.sensor_params;
      out << formatted("  sensors: imu %g Hz, joint_states %g Hz, odom %g Hz (lag %g s), seed %u\n", s.imu_rate_hz,
                       s.wheel_rate_hz, s.odometry_rate_hz, s.odometry_lag_s, s.seed);
    }
  } catch (const std::exception& e) {
    err << "tread_wear_drive: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace tread_wear
