#include "tread_wear/ros/bag/drive_cli.h"

#include <ros/time.h>

#include <cstdint>
#include <exception>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"

namespace tread_wear {
namespace {

const char* const kUsage =
    "usage: tread_wear_drive [--profile SPEED.csv] [--vehicle VEHICLE.yaml] [--rate-hz 50]\n"
    "                        [--lateral-accel-limit 3.0] [--seed N] [--sensors] --out DRIVE.bag\n"
    "  --profile   speed profile CSV (time_s, speed_kmh or speed_mps) [default: data/wltc_class3b.csv]\n"
    "  --vehicle   vehicle parameters [default: config/vehicle_passenger_car.yaml]\n"
    "  --rate-hz   sample rate of every input topic [Hz]\n"
    "  --lateral-accel-limit  a_y limit that sets the route's curve radii [m/s^2]\n"
    "  --seed      route random stream (deterministic per seed)\n"
    "  --sensors   also write what the car's sensors measured on the same drive: imu, joint_states, odom,\n"
    "              /tf_static (sensor model and its fixed parameters: docs/vehicle_inputs.md)\n";

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
  if (!args.parse(argc, argv, {"profile", "vehicle", "out", "rate-hz", "lateral-accel-limit", "seed"}, {"sensors"},
                  &error))
    return usage_error(error);
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
  options.sensors = args.has("sensors");
  const std::string profile_path = args.get("profile", share_dir + "/data/wltc_class3b.csv");
  const std::string vehicle_path = args.get("vehicle", share_dir + "/config/vehicle_passenger_car.yaml");
  const std::string bag_path = args.get("out");
  try {
    ros::Time::init();
    const SpeedProfile profile = loadSpeedProfile(profile_path);
    const VehicleModel vehicle(loadVehicleParams(vehicle_path));
    const Route route = buildRoute(profile, route_params);
    for (int w = 0; w < kWheelCount; ++w) options.wheel_names.push_back(wheelName(w));
    const DriveStats stats = writeDriveBag(bag_path, profile, route, vehicle, route_params, options);
    out << formatted(
        "%s: %s, %.0f s, %.2f km, %zu samples x 4 wheels at %g Hz, "
        "%zu curve events, max |a_y| %.2f m/s^2\n",
        bag_path.c_str(), profile.name().c_str(), stats.duration_s, stats.distance_m / 1000.0, stats.samples,
        options.rate_hz, route.events().size(), stats.max_abs_lateral_accel_mps2);
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
