// Drives between measurements (issue 26, part 3): the diagnosis' prediction of a drive segment, the model evaluated
// once per cell of the segment's points (diagnosis_bag.h, point_cells.h, extensions.h), equals the offline replay's
// wear for the same segment, which evaluates the model at every one of the drive's 180,000 steps per wheel
// (drive_replay.h). The WLTC class 3b drive of a passenger car, tread-depth checkpoints every 300 s on every wheel.
// The replay is the reference; the figures (printed) are in docs/diagnosis.md, "Drives between measurements".
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <std_msgs/Float64.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/diagnosis_bag.h"
#include "tread_wear/ros/bag/drive_bag_reader.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/ros/bag/replay_config.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
constexpr double kSegment_s = 300.0;  // time between checkpoints [s]
constexpr int kCheckpoints = 7;       // 0, 300, ..., 1800 s of drive time

TEST(DriveIntegration, SegmentPredictionEqualsTheReplaysWearOfTheSegment) {
  const ReplayConfig config = loadReplayConfig(kSource + "/config/vehicle_wheels.yaml");
  const SpeedProfile profile = loadSpeedProfile(kSource + "/data/wltc_class3b.csv");
  RouteParams route_params;
  const Route route = buildRoute(profile, route_params);
  DriveOptions options;
  for (const ReplayWheel& w : config.wheels) options.wheel_names.push_back(w.name);
  const std::string bag_path = ::testing::TempDir() + "drive_integration.bag";
  writeDriveBag(bag_path, profile, route, VehicleModel(loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml")),
                route_params, options);
  {
    // Tread-depth checkpoints; their values do not enter the prediction (only the measured wear).
    rosbag::Bag bag(bag_path, rosbag::bagmode::Append);
    for (const ReplayWheel& w : config.wheels)
      for (int j = 0; j < kCheckpoints; ++j) {
        std_msgs::Float64 depth;
        depth.data = 8e-3 - 1e-5 * j;
        bag.write("wheels/" + w.name + "/measured/tread_depth", ros::Time(kDriveTimeOffset_s + j * kSegment_s), depth);
      }
  }

  const TireParams& tire = config.wheels.front().tire;
  for (const ReplayWheel& w : config.wheels) ASSERT_EQ(w.tire.footprint.b_m, tire.footprint.b_m) << "one tire file";
  const RunTable table = diagnosis::readDiagnosisBag(bag_path, tire, config.settings);
  ASSERT_EQ(table.runs.size(), config.wheels.size() * (kCheckpoints - 1));
  const diagnosis::DiagnosisData data = diagnosis::buildDiagnosisData(table);
  const diagnosis::ExtendedModel model(tire, {config.settings.model.preset, config.settings.model.orientation}, {},
                                       data);
  // At the file's friction the prediction is the fine cells' own; at 0.8 times it, the fine cells carried by the
  // coarse ones' change (extensions.h), against a replay of a tire file with that friction.
  for (const double mu_scale : {1.0, 0.8}) {
    SCOPED_TRACE("mu_scale " + std::to_string(mu_scale));
    ReplayConfig scaled = config;
    for (ReplayWheel& w : scaled.wheels) {
      w.tire.friction.mu_0 *= mu_scale;
      w.tire.friction.mu_m *= mu_scale;
    }
    DriveReplay replay(scaled.settings, scaled.wheels);
    readDriveBag(bag_path, scaled, &replay);
    replay.run();
    diagnosis::Prediction prediction;
    ASSERT_TRUE(model.predict({1.0, mu_scale}, &prediction));

    // The replay's loss and distance at a checkpoint: its accumulators at the last step at or before it.
    auto at = [&](int wheel, double t_s) {
      const std::vector<StepRecord>& records = replay.records(wheel);
      const auto k =
          static_cast<std::size_t>(std::floor((t_s - replay.stepTime(0)) * config.settings.update_rate_hz + 1e-9));
      const StepRecord& r = records[std::min(k, records.size() - 1)];
      return std::make_pair(r.accumulated_loss_kg, r.distance_m);
    };
    double worst = 0.0, total_replay = 0.0, total_predicted = 0.0;
    std::printf("mu_scale %.2f\nwheel        segment  distance [m]  replay [mg]  integrated [mg]  error\n", mu_scale);
    for (std::size_t i = 0; i < table.runs.size(); ++i) {
      const int wheel = static_cast<int>(i) / (kCheckpoints - 1);
      const int j = static_cast<int>(i) % (kCheckpoints - 1);
      const auto [loss0, distance0] = at(wheel, kDriveTimeOffset_s + j * kSegment_s);
      const auto [loss1, distance1] = at(wheel, kDriveTimeOffset_s + (j + 1) * kSegment_s);
      const diagnosis::DiagnosisRun& run = data.runs[i];
      ASSERT_EQ(run.condition, replay.wheel(wheel).name + "/segment_" + std::to_string(j + 1));
      // The segmenter steps the replay's grid with its rules: the same distance to rounding.
      EXPECT_NEAR(run.drive_distance_m, distance1 - distance0, 1e-9 * distance1) << run.condition;
      const double replay_kg = loss1 - loss0;
      const double predicted_kg = prediction.wear_kg_per_m[i] * run.drive_distance_m;
      const double error = predicted_kg / replay_kg - 1.0;
      std::printf("%-12s %7d  %12.1f  %11.3f  %15.3f  %+.3f%%  (%zu points)\n", replay.wheel(wheel).name.c_str(),
                  j + 1, run.drive_distance_m, replay_kg * 1e6, predicted_kg * 1e6, 100.0 * error,
                  run.drive_points.size());
      worst = std::max(worst, std::abs(error));
      total_replay += replay_kg;
      total_predicted += predicted_kg;
    }
    std::printf("largest |error| %.3f%%, whole drive %+.4f%%; %zu fine cells, %zu coarse cells (brush evaluations "
                "per new parameter value)\n",
                100.0 * worst, 100.0 * (total_predicted / total_replay - 1.0), model.fineDriveCells(),
                model.evaluationPoints());
    EXPECT_LT(worst, 0.01);  // issue 26: within 1% of the replay's wear for the same segment
  }
}

}  // namespace
}  // namespace tread_wear
