// vehicle_inputs_node's parts without a master: the configuration's validate() errors (each names key, value and
// constraint), the rolling-radius file (round trip, missing, bad), and the per-wheel publish rule and quality fill.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <new>
#include <string>
#include <thread>

#include "common/temp_file.h"
#include "common/allocation_counter.h"
#include "tread_wear/io/rolling_radius_store.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/vehicle_inputs_config.h"
#include "tread_wear/ros/vehicle_inputs_node.h"
#include "tread_wear/ros/wear_markers.h"


namespace tread_wear {
namespace {

VehicleInputsConfig validConfig() {
  VehicleInputsConfig c;
  c.vehicle_params_file = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/vehicle_passenger_car.yaml";
  c.estimator.vehicle = loadVehicleParams(c.vehicle_params_file);
  return c;
}

std::string errorOf(const VehicleInputsConfig& c) {
  std::string error;
  EXPECT_FALSE(c.validate(&error));
  return error;
}

TEST(VehicleInputsConfig, DefaultsWithTheShippedVehicleAreValid) {
  std::string error;
  EXPECT_TRUE(validConfig().validate(&error)) << error;
  EXPECT_NE(validConfig().describe().find("speed_source: odom"), std::string::npos);
}

TEST(VehicleInputsConfig, EveryBadValueIsNamed) {
  VehicleInputsConfig c = validConfig();
  c.publish_rate_hz = 0.0;
  EXPECT_EQ(errorOf(c), "publish_rate_hz = 0: must be in (0, 1000] [Hz]");
  c = validConfig();
  c.publish_rate_hz = 5000.0;
  EXPECT_NE(errorOf(c).find("publish_rate_hz = 5000"), std::string::npos);
  c = validConfig();
  c.speed_source = "gnss";
  EXPECT_EQ(errorOf(c), "speed_source = 'gnss': must be odom or twist");
  c = validConfig();
  c.base_frame = "";
  EXPECT_EQ(errorOf(c), "base_frame: must not be empty");
  c = validConfig();
  c.wheel_joints[2] = c.wheel_joints[0];
  EXPECT_NE(errorOf(c).find("wheel_joints = 'wheel_front_left_joint': must be non-empty and unique"),
            std::string::npos);
  c = validConfig();
  c.wheel_names[3] = "";
  EXPECT_NE(errorOf(c).find("wheel_names"), std::string::npos);
  c = validConfig();
  c.steering_joint = c.wheel_joints[1];
  EXPECT_NE(errorOf(c).find("steering_joint = 'wheel_front_right_joint'"), std::string::npos);
  c = validConfig();
  c.wheel_velocity_signs[1] = 0.5;
  EXPECT_EQ(errorOf(c), "wheel_velocity_signs: 0.5: each must be 1 or -1");
  c = validConfig();
  c.marker_rate_hz = 200.0;
  EXPECT_NE(errorOf(c).find("marker_rate_hz = 200"), std::string::npos);
  c = validConfig();
  c.tf_timeout_s = 2.0;
  EXPECT_NE(errorOf(c).find("tf_timeout_s = 2"), std::string::npos);
  c = validConfig();
  c.save_interval_s = 0.0;
  EXPECT_NE(errorOf(c).find("save_interval_s = 0"), std::string::npos);
  c = validConfig();
  c.cog_position_m[1] = std::nan("");
  EXPECT_NE(errorOf(c).find("cog_position_m"), std::string::npos);
  // The estimator's own validate(), prefixed with estimator/.
  c = validConfig();
  c.estimator.steering_ratio = -1.0;
  EXPECT_EQ(errorOf(c).rfind("estimator: ", 0), 0u);
  EXPECT_NE(errorOf(c).find("steering_ratio"), std::string::npos);
  c = validConfig();
  c.estimator.imu_timeout_s = 0.0;
  EXPECT_NE(errorOf(c).find("imu_timeout_s"), std::string::npos);
}

TEST(RollingRadiusStore, RoundTripMissingAndBadFiles) {
  const std::array<std::string, kWheelCount> names{{"front_left", "front_right", "rear_left", "rear_right"}};
  std::array<RollingRadiusState, kWheelCount> state{};
  for (int i = 0; i < kWheelCount; ++i) state[i] = {0.30 + 0.001 * i, 1234.5 + i};
  const std::string path = testing::TempDir() + "tread_wear_radii_test.json";
  std::remove(path.c_str());
  std::array<RollingRadiusState, kWheelCount> loaded{};
  std::string error;
  EXPECT_EQ(loadRollingRadii(path, names, &loaded, &error), RadiusLoadStatus::kMissing);
  ASSERT_TRUE(saveRollingRadii(path, names, state, 1.7e9, &error)) << error;
  ASSERT_EQ(loadRollingRadii(path, names, &loaded, &error), RadiusLoadStatus::kLoaded) << error;
  for (int i = 0; i < kWheelCount; ++i) {
    EXPECT_EQ(loaded[i].radius_m, state[i].radius_m);
    EXPECT_EQ(loaded[i].learned_distance_m, state[i].learned_distance_m);
  }
  std::remove(path.c_str());
  TempFile garbage("{not json", ".json");
  EXPECT_EQ(loadRollingRadii(garbage.path(), names, &loaded, &error), RadiusLoadStatus::kInvalid);
  std::string text = rollingRadiiJson(names, state, 0.0);
  const std::string first = "\"radius_m\": 0.3\n";
  const std::size_t at = text.find(first);
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, first.size(), "\"radius_m\": -0.3\n");
  EXPECT_FALSE(parseRollingRadiiJson(text, names, &loaded, &error));
  EXPECT_NE(error.find("front_left"), std::string::npos) << error;
  std::array<std::string, kWheelCount> other = names;
  other[3] = "spare";
  EXPECT_FALSE(parseRollingRadiiJson(rollingRadiiJson(names, state, 0.0), other, &loaded, &error));
  EXPECT_EQ(error, "wheel spare missing");
}

TEST(VehicleInputsNodeParts, InvalidWheelIsNotPublishableAndItsQualityIsFilled) {
  VehicleInputEstimate e;
  e.valid = true;
  for (auto& w : e.wheels) {
    w.load_quality = w.slip_angle_quality = w.slip_ratio_quality = EstimateQuality::kGood;
    w.load_n = 4000.0;
    w.speed_mps = 10.0;
  }
  EXPECT_TRUE(wheelPublishable(e, 0));
  e.wheels[1].slip_ratio_quality = EstimateQuality::kInvalid;
  e.wheels[1].slip_ratio = std::nan("");
  e.wheels[1].flags = kFlagWheelSpeedMissing;
  EXPECT_FALSE(wheelPublishable(e, 1));
  tread_wear::WheelInputQuality q;
  fillInputQuality(e, 1, false, &q);
  EXPECT_EQ(q.slip_ratio_quality, tread_wear::WheelInputQuality::QUALITY_INVALID);
  EXPECT_EQ(q.flags, tread_wear::WheelInputQuality::FLAG_WHEEL_SPEED_MISSING);
  EXPECT_FALSE(q.published);
  e.valid = false;  // no speed source: nothing is publishable, every quality invalid
  EXPECT_FALSE(wheelPublishable(e, 0));
  fillInputQuality(e, 0, false, &q);
  EXPECT_EQ(q.load_quality, tread_wear::WheelInputQuality::QUALITY_INVALID);
  // The message's constants are the estimator's enumerations.
  EXPECT_EQ(tread_wear::WheelInputQuality::FLAG_NO_IMU, static_cast<unsigned>(kFlagNoImu));
  EXPECT_EQ(tread_wear::WheelInputQuality::FLAG_LOW_SPEED, static_cast<unsigned>(kFlagLowSpeed));
  EXPECT_EQ(tread_wear::WheelInputQuality::QUALITY_LOW_SPEED, static_cast<int>(EstimateQuality::kLowSpeed));
}

TEST(VehicleMarkers, BodyWheelsAndPerWheelLabelsWithLoadSlipAndWear) {
  const VehicleInputsConfig c = validConfig();
  VehicleInputEstimate e;
  e.valid = true;
  e.speed_mps = 15.0;
  for (auto& w : e.wheels) {
    w.load_quality = w.slip_angle_quality = w.slip_ratio_quality = EstimateQuality::kGood;
    w.load_n = 4250.0;
    w.slip_angle_rad = -0.5 * M_PI / 180.0;
    w.slip_ratio = 0.0012;
    w.speed_mps = 15.0;
  }
  e.wheels[0].steer_angle_rad = 0.1;
  std::array<WheelWearView, kWheelCount> wear{};
  wear[1].wear_rate_kg_per_m = 12.5e-9;  // 12.5 mg/km
  wear[1].accumulated_loss_kg = 0.25e-6;
  visualization_msgs::MarkerArray a;
  appendVehicleMarkers(c, e, wear, ros::Time(3.0), &a);
  ASSERT_EQ(a.markers.size(), 1u + 4u + 1u + 4u);
  EXPECT_EQ(a.markers[0].ns, "vehicle/body");
  EXPECT_EQ(a.markers[0].header.frame_id, "base_link");
  // Wheels at the vehicle's geometry about the CoG (base_link on the ground below it).
  EXPECT_NEAR(a.markers[1].pose.position.x, 1.06, 1e-12);
  EXPECT_NEAR(a.markers[1].pose.position.y, 0.775, 1e-12);
  EXPECT_NEAR(a.markers[4].pose.position.x, -1.58, 1e-12);
  EXPECT_NEAR(a.markers[4].pose.position.y, -0.76, 1e-12);
  EXPECT_EQ(a.markers[5].ns, "vehicle/label");
  EXPECT_EQ(a.markers[6].ns, "vehicle/wheel_labels");
  EXPECT_EQ(a.markers[6].header.frame_id, "wheel_front_left");
  EXPECT_EQ(a.markers[6].text, "front_left\nFz 4.25 kN\nalpha -0.50 deg, kappa 0.0012");
  EXPECT_EQ(a.markers[7].text, "front_right\nFz 4.25 kN\nalpha -0.50 deg, kappa 0.0012\nwear 12.50 mg/km, loss 0.250 mg");
  e.valid = false;  // nothing published: said in the label, labels red
  visualization_msgs::MarkerArray b;
  appendVehicleMarkers(c, e, wear, ros::Time(3.0), &b);
  EXPECT_EQ(b.markers[5].text, "no speed source: nothing published");
  EXPECT_GT(b.markers[6].color.r, 0.9f);
  EXPECT_LT(b.markers[6].color.g, 0.5f);
}

TEST(WearMarkers, PatchLabelWithTheStepInputsSaysWhyTheWheelWears) {
  WheelInputs inputs;
  inputs.setLoad(1.0, 4250.0);
  inputs.setSlip(1.0, -2.0 * M_PI / 180.0, 0.01, 0.0);
  inputs.setSpeed(1.0, 15.0);
  WheelOutput out;
  out.status = WheelStatus::kOk;
  out.accumulated_loss_kg = 1.5e-6;
  out.distance_m = 2500.0;
  out.result.wear_rate_kg_per_m = 8e-7;  // 800 mg/km
  out.result.slide_fraction = 0.25;
  visualization_msgs::MarkerArray a;
  appendWheelMarkers("fl", "wheel_fl", ros::Time(1.0), PatchFields(), out.result, out, &a, &inputs);
  ASSERT_EQ(a.markers.size(), 1u);
  EXPECT_EQ(a.markers[0].text,
            "fl (ok)\n1.500 mg, 2.500 km, slide 25%\nFz 4.25 kN, alpha -2.00 deg, kappa 0.0100\nwear 800.00 mg/km");
}

TEST(VehicleInputsNodeParts, TheCycleAllocatesNothingAndPublishesTheStaticLoads) {
  VehicleInputsConfig c = validConfig();
  VehicleInputEstimator estimator(c.estimator);
  std::mutex mutex;
  std::array<double, kWheelCount> last_load{};
  std::atomic<int> loads{0}, qualities{0};
  std::array<VehicleInputPublishers, kWheelCount> pubs;
  for (int i = 0; i < kWheelCount; ++i) {
    pubs[i].load = std::make_unique<RealtimePublisher<tread_wear::WheelLoad>>(
        RealtimePublisher<tread_wear::WheelLoad>::Sink([&, i](const tread_wear::WheelLoad& m) {
          std::lock_guard<std::mutex> l(mutex);
          last_load[i] = m.load_n;
          ++loads;
        }));
    pubs[i].slip = std::make_unique<RealtimePublisher<tread_wear::WheelSlip>>(
        RealtimePublisher<tread_wear::WheelSlip>::Sink([](const tread_wear::WheelSlip&) {}));
    pubs[i].speed = std::make_unique<RealtimePublisher<tread_wear::WheelSpeed>>(
        RealtimePublisher<tread_wear::WheelSpeed>::Sink([](const tread_wear::WheelSpeed&) {}));
    pubs[i].quality = std::make_unique<RealtimePublisher<tread_wear::WheelInputQuality>>(
        RealtimePublisher<tread_wear::WheelInputQuality>::Sink([&](const tread_wear::WheelInputQuality&) { ++qualities; }));
    pubs[i].quality->msg().wheel = "wheel name set once";
  }
  CycleStats stats;
  VehicleInputEstimate estimate;
  const double v = 15.0, g = c.estimator.vehicle.gravity_mps2;
  long cycle_allocations = 0;
  for (int k = 0; k < 200; ++k) {
    const double t = 0.01 * k;
    estimator.addImu(t, 0.0, 0.0, g, 0.0, 0.0, 0.0);
    estimator.addWheelSpeeds(t, {v / 0.31, v / 0.31, v / 0.31, v / 0.31});
    estimator.addSteering(t, 0.0);
    estimator.addSpeed(t, v);
    const long before = t_allocations;
    estimator.estimate(t, &estimate);
    publishWheelInputs(estimate, ros::Time(100.0 + t), &pubs, &stats);
    if (k > 0) cycle_allocations += t_allocations - before;
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // let the publisher threads take the messages
  }
  EXPECT_EQ(cycle_allocations, 0);
  for (auto& p : pubs) {
    p.load->stop();
    p.slip->stop();
    p.speed->stop();
    p.quality->stop();
  }
  EXPECT_GT(loads.load(), 4 * 150);
  EXPECT_GT(qualities.load(), 4 * 150);
  const VehicleParams& vp = c.estimator.vehicle;
  for (int i = 0; i < kWheelCount; ++i) {
    const double expected = vp.mass_kg * g * (i < 2 ? vp.cogToRearAxle_m() : vp.cog_to_front_axle_m) /
                            vp.wheelbase_m / 2.0;
    EXPECT_NEAR(last_load[i], expected, 0.02 * expected) << i;
  }
  EXPECT_EQ(stats.withheld[0] + stats.published[0], 200u);
}

}  // namespace
}  // namespace tread_wear
