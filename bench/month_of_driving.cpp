// tread_wear_month_bench: writes a month of driving as one rosbag for timing the diagnosis of drives (issue 26,
// part 3; docs/diagnosis.md, "Drives between measurements"). The drives are the WLTC class 3b of the passenger car
// (config/vehicle_wheels.yaml), `--drives-per-day` a day for `--days` days at 06:00 and 18:00, each over its own
// route (seeded) in turn by a calm, normal and aggressive driver; inputs at --rate-hz. Every wheel gets a tread
// depth checkpoint before the first drive and every --checkpoint-days days. The depths are the model's own wear
// (the diagnosis' integrated prediction at the `standard` preset with w3 x 1.1) plus a gauge error of
// --gauge-sigma-m: a timing case, not a proof (the proof cases are the harness's).
//   tread_wear_month_bench --out month.bag
//   time tread_wear_diagnose --params config/tires/passenger_205_55_r16.yaml --bag month.bag --report DIR --no-plots
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/Float64.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <random>

#include "tread_wear/cli/command_line.h"
#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/estimation/drive_segments.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_reader.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/ros/bag/replay_config.h"
#include "tread_wear/vehicle/driving_style.h"

namespace tread_wear {
namespace {

constexpr double kDay_s = 86400.0;
constexpr double kTrueW3Scale = 1.1;
constexpr double kNewTreadDepth_m = 8e-3;

int run(int argc, const char* const argv[]) {
  CommandLine a;
  std::string error;
  if (!a.parse(argc, argv, {"out", "days", "drives-per-day", "rate-hz", "checkpoint-days", "seed", "gauge-sigma-m"}, {},
               &error) ||
      !a.has("out")) {
    std::cerr << "usage: tread_wear_month_bench --out FILE.bag [--days 30] [--drives-per-day 2] [--rate-hz 10]\n"
                 "       [--checkpoint-days 7] [--seed 1] [--gauge-sigma-m 2e-6]\n"
              << error << "\n";
    return 2;
  }
  int days = 30, per_day = 2, checkpoint_days = 7, seed = 1;
  double rate_hz = 10.0, gauge_sigma_m = 2e-6;
  if (!a.integer("days", &days, &error) || !a.integer("drives-per-day", &per_day, &error) ||
      !a.integer("checkpoint-days", &checkpoint_days, &error) || !a.integer("seed", &seed, &error) ||
      !a.number("rate-hz", &rate_hz, &error) || !a.number("gauge-sigma-m", &gauge_sigma_m, &error) || days < 1 ||
      per_day < 1 || per_day > 4 || checkpoint_days < 1 || !(rate_hz > 0.0) || !(gauge_sigma_m >= 0.0)) {
    std::cerr << "tread_wear_month_bench: bad option " << error << "\n";
    return 2;
  }
  const std::string share = TREAD_WEAR_SHARE_DIR;
  const ReplayConfig config = loadReplayConfig(share + "/config/vehicle_wheels.yaml");
  const VehicleModel vehicle(loadVehicleParams(share + "/config/vehicle_passenger_car.yaml"));
  const SpeedProfile profile = loadSpeedProfile(share + "/data/wltc_class3b.csv");
  const int wheels = static_cast<int>(config.wheels.size());
  std::map<std::string, std::pair<int, InputKind>> routes;
  for (int w = 0; w < wheels; ++w) {
    const std::string prefix = "/wheels/" + config.wheels[w].name + "/";
    routes[prefix + "load"] = {w, InputKind::kLoad};
    routes[prefix + "slip"] = {w, InputKind::kSlip};
    routes[prefix + "speed"] = {w, InputKind::kSpeed};
  }
  // Checkpoints: before the first drive, then every checkpoint_days days (and after the last drive).
  std::vector<double> checkpoints;
  for (int d = 0; d <= days; d += checkpoint_days) checkpoints.push_back(kDriveTimeOffset_s + d * kDay_s);
  if (checkpoints.back() < kDriveTimeOffset_s + days * kDay_s) checkpoints.push_back(kDriveTimeOffset_s + days * kDay_s);
  std::vector<std::unique_ptr<DriveSegmenter>> segmenters;
  for (int w = 0; w < wheels; ++w)
    segmenters.push_back(std::make_unique<DriveSegmenter>(config.settings, PointCellParams(), checkpoints,
                                                          kDriveTimeOffset_s));

  rosbag::Bag month(a.get("out"), rosbag::bagmode::Write);
  const std::string scratch = a.get("out") + ".drive.bag";
  const char* styles[] = {"calm", "normal", "aggressive"};
  double driving_s = 0.0, distance_m = 0.0;
  std::size_t messages = 0;
  for (int day = 0; day < days; ++day)
    for (int slot = 0; slot < per_day; ++slot) {
      const int k = day * per_day + slot;
      RouteParams route_params;
      route_params.seed = static_cast<std::uint32_t>(seed * 1000 + k);
      const Route route = buildRoute(profile, route_params);
      DrivingEnvelope envelope;
      drivingStyle(styles[k % 3], &envelope);
      const EnvelopeDrive drive = driveWithinEnvelope(profile, route, envelope);
      DriveOptions options;
      options.rate_hz = rate_hz;
      for (const ReplayWheel& w : config.wheels) options.wheel_names.push_back(w.name);
      const DriveStats stats = writeDriveBag(scratch, drive.trace, {profile.name(), 0.0, 0.0, drive.phases, {}},
                                             vehicle, route_params, options);
      driving_s += stats.duration_s;
      distance_m += stats.distance_m;
      // Drive time 0 at 06:00 (+ 12 h per slot) of the day, 1 s after a checkpoint at midnight.
      const double offset_s = day * kDay_s + 6 * 3600.0 + slot * 12 * 3600.0;
      rosbag::Bag drive_bag(scratch, rosbag::bagmode::Read);
      for (const rosbag::MessageInstance& m : rosbag::View(drive_bag)) {
        const auto route_it = routes.find(m.getTopic());
        if (route_it == routes.end()) continue;
        month.write(m.getTopic(), m.getTime() + ros::Duration(offset_s), m);
        InputSample sample = inputSample(m, route_it->second.second);
        sample.t_s += offset_s;
        segmenters[route_it->second.first]->addSample(sample);
        ++messages;
      }
    }
  std::remove(scratch.c_str());

  // Depths: the diagnosis' own prediction of each segment with w3 x 1.1, plus the gauge error.
  RunTable table;
  for (int w = 0; w < wheels; ++w)
    for (const DriveSegment& s : segmenters[w]->finish()) {
      RunRecord r = driveSegmentRecord(s);
      r.measured_wear_rate_kg_per_m = 1.0;
      r.condition_id = config.wheels[w].name + "/" + std::to_string(table.runs.size());
      table.runs.push_back(r);
    }
  const TireParams& tire = config.wheels.front().tire;
  const diagnosis::DiagnosisData data = diagnosis::buildDiagnosisData(table);
  const diagnosis::ExtendedModel truth(tire, {Preset::kStandard, config.settings.model.orientation}, {}, data);
  diagnosis::Prediction prediction;
  if (!truth.predict({kTrueW3Scale, 1.0}, &prediction)) throw std::runtime_error("the truth cannot be evaluated");
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::normal_distribution<double> gauge(0.0, gauge_sigma_m);
  const double mass_per_depth = tire.material.massPerDepth_kg_per_m();
  const std::size_t segments = checkpoints.size() - 1;
  for (int w = 0; w < wheels; ++w) {
    double depth_m = kNewTreadDepth_m;
    for (std::size_t j = 0; j < checkpoints.size(); ++j) {
      if (j > 0) {
        const diagnosis::DiagnosisRun& run = data.runs[w * segments + j - 1];
        depth_m -= prediction.wear_kg_per_m[w * segments + j - 1] * run.drive_distance_m / mass_per_depth;
      }
      std_msgs::Float64 msg;
      msg.data = depth_m + gauge(rng);
      month.write("/wheels/" + config.wheels[w].name + "/measured/tread_depth", ros::Time(checkpoints[j]), msg);
    }
  }
  month.close();
  std::printf("%s: %d days, %d drives, %.1f h of driving, %.0f km, %zu input messages, %zu segments x %d wheels, "
              "%zu fine and %zu coarse cells\n",
              a.get("out").c_str(), days, days * per_day, driving_s / 3600.0, distance_m / 1000.0, messages, segments,
              wheels, truth.fineDriveCells(), truth.evaluationPoints());
  return 0;
}

}  // namespace
}  // namespace tread_wear

int main(int argc, char** argv) {
  try {
    return tread_wear::run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "tread_wear_month_bench: " << e.what() << "\n";
    return 1;
  }
}
