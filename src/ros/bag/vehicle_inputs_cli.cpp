#include "tread_wear/ros/bag/vehicle_inputs_cli.h"

#include <ros/time.h>

#include <algorithm>
#include <exception>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/vehicle_inputs_config.h"
#include "tread_wear/ros/bag/vehicle_inputs_bag.h"

namespace tread_wear {
namespace {

const char* const kUsage =
    "usage: tread_wear_vehicle_inputs IN.bag OUT.bag [--config INPUTS.yaml] [--vehicle VEHICLE.yaml]\n"
    "                                 [--rate-hz 100] [--wheel-radius 0.305] [--steering-ratio 15]\n"
    "                                 [--no-wheel-speeds]\n"
    "  IN.bag          sensor topics imu, joint_states, odom and the IMU mount on /tf_static\n"
    "                  (e.g. tread_wear_drive --sensors); if it also holds wheels/<name>/*, the estimate is\n"
    "                  scored against them\n"
    "  OUT.bag         wheels/<name>/{load,slip,speed} for tread_wear_replay, what vehicle_inputs_node with the\n"
    "                  same configuration and input_time publishes when IN.bag is played to it\n"
    "  --config        the front end's configuration, the node's file [default: config/vehicle_inputs.yaml]\n"
    "  --vehicle       vehicle parameters [default: config/vehicle_passenger_car.yaml]\n"
    "  the options below replace the configuration's value:\n"
    "  --rate-hz       publish_rate_hz, the cycle and output rate [Hz]\n"
    "  --wheel-radius  estimator/wheel_radius_m of every wheel [m] (learned online from there)\n"
    "  --steering-ratio  estimator/steering_ratio, steering-wheel angle per road-wheel angle [-]\n"
    "  --no-wheel-speeds  use_wheel_speeds: false, as a car without wheel-speed signals (slip ratios from the\n"
    "                  force demand)\n";

}  // namespace

int runVehicleInputsCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out,
                        std::ostream& err) {
  auto usage_error = [&err](const std::string& message) {
    return usageError(err, "tread_wear_vehicle_inputs", message, kUsage);
  };
  CommandLine args;
  std::string error;
  if (!args.parse(argc, argv, {"config", "vehicle", "rate-hz", "wheel-radius", "steering-ratio"}, {"no-wheel-speeds"},
                  &error, 2))
    return usage_error(error);
  if (args.help()) {
    out << kUsage;
    return 0;
  }
  double rate_hz = 0.0, radius = 0.0, steering_ratio = 0.0;
  if (!args.number("rate-hz", &rate_hz, &error) || !args.number("wheel-radius", &radius, &error) ||
      !args.number("steering-ratio", &steering_ratio, &error))
    return usage_error(error);
  if (args.positional().size() != 2) return usage_error("needs IN.bag and OUT.bag");
  if (args.has("rate-hz") && !(rate_hz > 0.0)) return usage_error("--rate-hz must be > 0");
  if (args.has("wheel-radius") && !(radius > 0.0)) return usage_error("--wheel-radius must be > 0");
  if (args.has("steering-ratio") && !(steering_ratio > 0.0)) return usage_error("--steering-ratio must be > 0");
  const std::string in_path = args.positional()[0], out_path = args.positional()[1];
  const std::string config_path = args.get("config", share_dir + "/config/vehicle_inputs.yaml");
  const std::string vehicle_path = args.get("vehicle", share_dir + "/config/vehicle_passenger_car.yaml");
  try {
    ros::Time::init();
    VehicleInputsOptions options;
    options.config = loadVehicleInputsConfigFile(config_path, vehicle_path);
    VehicleInputsConfig& c = options.config;
    if (args.has("rate-hz")) c.publish_rate_hz = rate_hz;
    if (args.has("wheel-radius")) c.estimator.wheel_radius_m.fill(radius);
    if (args.has("steering-ratio")) c.estimator.steering_ratio = steering_ratio;
    if (args.has("no-wheel-speeds")) c.use_wheel_speeds = false;
    const VehicleInputsResult r = runVehicleInputs(in_path, out_path, options);
    out << formatted("%s: imu %zu, joint_states %zu, odom %zu messages; IMU mount roll %.3f pitch %.3f yaw %.3f deg "
                     "at (%.3f, %.3f, %.3f) m, odom latency %.3f s\n",
                     in_path.c_str(), r.imu_messages, r.joint_state_messages, r.odometry_messages,
                     r.imu_mount_rpy_rad[0] * 57.29577951308232, r.imu_mount_rpy_rad[1] * 57.29577951308232,
                     r.imu_mount_rpy_rad[2] * 57.29577951308232, r.imu_position_m[0], r.imu_position_m[1],
                     r.imu_position_m[2], r.odometry_lag_s);
    out << formatted("%s: %zu cycles at %g Hz (%zu without a speed source), %llu rejected samples\n",
                     out_path.c_str(), r.cycles, c.publish_rate_hz, r.invalid_cycles,
                     static_cast<unsigned long long>(r.rejected_samples));
    for (int s = 0; s < kSensorCount; ++s) {
      for (int f = 1; f < kSampleFaultCount; ++f) {
        const std::uint64_t n = r.faults[static_cast<std::size_t>(s)][static_cast<std::size_t>(f)];
        if (n > 0)
          out << formatted("  %s %s: %llu%s\n", sensorName(static_cast<Sensor>(s)),
                           sampleFaultName(static_cast<SampleFault>(f)), static_cast<unsigned long long>(n),
                           static_cast<SampleFault>(f) == SampleFault::kStale ? " cycles" : " samples rejected");
      }
    }
    for (int w = 0; w < kWheelCount; ++w) {
      const auto i = static_cast<std::size_t>(w);
      out << formatted("  %-11s rolling radius %.5f m over %.0f m%s\n", wheelName(w), r.radii[i].radius_m,
                       r.radii[i].learned_distance_m, r.radius_converged[i] ? "" : " (not converged)");
    }
    if (r.truth_present) {
      out << "error against the true inputs (RMS / worst, scored share):\n"
          << "| wheel | load, % of static | slip angle, deg | slip ratio (radius converged) | wheel speed, m/s |\n"
          << "|---|---|---|---|---|\n";
      auto row = [&out](const char* name, const ErrorStat& l, const ErrorStat& a, const ErrorStat& k,
                        const ErrorStat& v) {
        out << formatted("| %s | %.3f / %.3f (%.0f %%) | %.4f / %.4f (%.0f %%) | %.5f / %.5f (%.0f %%) | "
                         "%.4f / %.4f |\n",
                         name, 100.0 * l.rms(), 100.0 * l.worst, 100.0 * l.scoredShare(), a.rms(), a.worst,
                         100.0 * a.scoredShare(), k.rms(), k.worst, 100.0 * k.scoredShare(), v.rms(), v.worst);
      };
      ErrorStat all_l, all_a, all_k, all_v;
      auto merge = [](ErrorStat* into, const ErrorStat& s) {
        into->sum_sq += s.sum_sq;
        into->worst = std::max(into->worst, s.worst);
        into->scored += s.scored;
        into->skipped += s.skipped;
      };
      for (int w = 0; w < kWheelCount; ++w) {
        const auto i = static_cast<std::size_t>(w);
        row(wheelName(w), r.load[i], r.slip_angle[i], r.slip_ratio[i], r.speed[i]);
        merge(&all_l, r.load[i]);
        merge(&all_a, r.slip_angle[i]);
        merge(&all_k, r.slip_ratio[i]);
        merge(&all_v, r.speed[i]);
      }
      row("all", all_l, all_a, all_k, all_v);
    }
  } catch (const std::exception& e) {
    err << "tread_wear_vehicle_inputs: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}

}  // namespace tread_wear
