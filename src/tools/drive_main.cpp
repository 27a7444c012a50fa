// tread_wear_drive: generates a test drive (speed profile + route + vehicle model) as a bag of the node's inputs.
// Usage and model: docs/drive.md.
#include <ros/time.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/bag_io.h"

namespace {

const char* const kUsage =
    "usage: tread_wear_drive [--profile SPEED.csv] [--vehicle VEHICLE.yaml] [--rate-hz 50]\n"
    "                        [--lateral-accel-limit 3.0] [--seed N] --out DRIVE.bag\n"
    "  --profile   speed profile CSV (time_s, speed_kmh or speed_mps) [default: data/wltc_class3b.csv]\n"
    "  --vehicle   vehicle parameters [default: config/vehicle_passenger_car.yaml]\n"
    "  --rate-hz   sample rate of every input topic [Hz]\n"
    "  --lateral-accel-limit  a_y limit that sets the route's curve radii [m/s^2]\n"
    "  --seed      route random stream (deterministic per seed)\n";

}  // namespace

int main(int argc, char** argv) {
  const std::string share = TREAD_WEAR_SHARE_DIR;
  tread_wear::DriveOptions options;
  tread_wear::RouteParams route_params;
  auto usage_error = [](const std::string& message) {
    return tread_wear::usageError(std::cerr, "tread_wear_drive", message, kUsage);
  };
  tread_wear::CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"profile", "vehicle", "out", "rate-hz", "lateral-accel-limit", "seed"}, {}, &error))
    return usage_error(error);
  if (args.help()) {
    std::fputs(kUsage, stdout);
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
  const std::string profile_path = args.get("profile", share + "/data/wltc_class3b.csv");
  const std::string vehicle_path = args.get("vehicle", share + "/config/vehicle_passenger_car.yaml");
  const std::string out = args.get("out");
  try {
    ros::Time::init();
    const tread_wear::SpeedProfile profile = tread_wear::loadSpeedProfile(profile_path);
    const tread_wear::VehicleModel vehicle(tread_wear::loadVehicleParams(vehicle_path));
    const tread_wear::Route route = tread_wear::buildRoute(profile, route_params);
    for (int w = 0; w < tread_wear::kWheelCount; ++w) options.wheel_names.push_back(tread_wear::wheelName(w));
    const tread_wear::DriveStats stats =
        tread_wear::writeDriveBag(out, profile, route, vehicle, route_params, options);
    std::printf("%s: %s, %.0f s, %.2f km, %zu samples x 4 wheels at %g Hz, %zu curve events, max |a_y| %.2f m/s^2\n",
                out.c_str(), profile.name().c_str(), stats.duration_s, stats.distance_m / 1000.0, stats.samples,
                options.rate_hz, route.events().size(), stats.max_abs_lateral_accel_mps2);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tread_wear_drive: %s\n", e.what());
    return 1;
  }
  return 0;
}
