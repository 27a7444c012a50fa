// tread_wear_drive: generates a test drive (speed profile + route + vehicle model) as a bag of the node's inputs.
// Usage and model: docs/drive.md.
#include <ros/time.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "bag_io.h"

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
  std::string profile_path = share + "/data/wltc_class3b.csv", vehicle_path = share + "/config/vehicle_passenger_car.yaml";
  std::string out;
  tread_wear::DriveOptions options;
  tread_wear::RouteParams route_params;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--profile" && has_value) {
      profile_path = argv[++i];
    } else if (arg == "--vehicle" && has_value) {
      vehicle_path = argv[++i];
    } else if (arg == "--out" && has_value) {
      out = argv[++i];
    } else if (arg == "--rate-hz" && has_value) {
      options.rate_hz = std::atof(argv[++i]);
    } else if (arg == "--lateral-accel-limit" && has_value) {
      route_params.lateral_accel_limit_mps2 = std::atof(argv[++i]);
    } else if (arg == "--seed" && has_value) {
      route_params.seed = static_cast<std::uint32_t>(std::strtoul(argv[++i], nullptr, 10));
    } else {
      std::fprintf(stderr, "tread_wear_drive: unknown or incomplete argument '%s'\n%s", arg.c_str(), kUsage);
      return 2;
    }
  }
  if (out.empty() || !(options.rate_hz > 0.0)) {
    std::fprintf(stderr, "tread_wear_drive: --out is required and --rate-hz must be > 0\n%s", kUsage);
    return 2;
  }
  try {
    ros::Time::init();
    const tread_wear::SpeedProfile profile = tread_wear::SpeedProfile::load(profile_path);
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
