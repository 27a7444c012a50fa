// VehicleInputPipeline, the one front end of vehicle_inputs_node and tread_wear_vehicle_inputs: the speed rule
// (analytic), joints by name with their signs, the IMU mount, input time independent of the order in which the
// topics arrive (the property the node-versus-tool rostest relies on), a looped bag, bad input, and no allocation in
// the intake and the cycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/allocation_counter.h"
#include "tread_wear/estimation/vehicle_input_pipeline.h"
#include "tread_wear/io/vehicle_params_io.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kG = 9.81;
const std::vector<std::string> kJoints{"wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint",
                                       "wheel_rear_right_joint", "steering_wheel_joint"};

VehicleInputsConfig config() {
  VehicleInputsConfig c;
  c.estimator.vehicle = loadVehicleParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/vehicle_passenger_car.yaml");
  c.cog_position_m = {0.0, 0.0, 0.0};
  return c;
}

/// One sensor message of a straight drive at 15 m/s, accelerating at 0.5 m/s^2 (IMU and joints at 100 Hz, odometry
/// at 10 Hz stamped at its measurement), with the time it is delivered at.
struct Message {
  enum Kind { kImu, kJoints, kSpeed } kind;
  double stamp_s;
  double value;      ///< speed [m/s] (odometry) or wheel angular speed [rad/s] (joints)
  double arrival_s;  ///< when the driver gets it [s]
};

/// The drive's messages in the order of their arrival: joints `joints_late_s` after the IMU of the same stamp,
/// odometry `speed_late_s` after its stamp.
std::vector<Message> drive(double t0, double duration_s, double joints_late_s, double speed_late_s) {
  std::vector<Message> messages;
  for (int k = 0; k * 0.01 <= duration_s + 1e-9; ++k) {
    const double t = t0 + k * 0.01, v = 15.0 + 0.5 * k * 0.01;
    messages.push_back({Message::kImu, t, 0.0, t});
    messages.push_back({Message::kJoints, t, v / 0.31, t + joints_late_s});
    if (k % 10 == 0) messages.push_back({Message::kSpeed, t, v, t + speed_late_s});
  }
  std::stable_sort(messages.begin(), messages.end(),
                   [](const Message& a, const Message& b) { return a.arrival_s < b.arrival_s; });
  return messages;
}

/// Feeds the messages as a driver in input time does; the per-wheel inputs of every cycle, in order.
std::vector<VehicleInputEstimate> play(const std::vector<Message>& messages) {
  VehicleInputsConfig c = config();
  c.input_time = true;
  VehicleInputPipeline pipeline(c);
  EXPECT_TRUE(pipeline.setImuMount({{0.0, 0.0, 0.0, 1.0}}, {{0.2, 0.0, 0.1}}));
  std::vector<VehicleInputEstimate> cycles;
  auto keep = [&](double) { cycles.push_back(pipeline.estimate()); };
  double end_s = 0.0;
  for (const Message& m : messages) {
    if (m.kind == Message::kSpeed) {
      pipeline.addSpeed(m.stamp_s, m.value, 0.0);
      continue;
    }
    end_s = std::max(end_s, m.stamp_s);
    if (m.kind == Message::kImu) {
      pipeline.cyclesBefore(InputStream::kImu, m.stamp_s, keep);
      pipeline.addImu(m.stamp_s, {{0.5, 0.0, kG}}, {{0.0, 0.0, 0.0}});
    } else {
      pipeline.cyclesBefore(InputStream::kJoints, m.stamp_s, keep);
      pipeline.addJoints(m.stamp_s, kJoints, {0, 0, 0, 0, 0}, {m.value, m.value, m.value, m.value, 0.0});
    }
  }
  pipeline.cyclesThrough(end_s, keep);
  return cycles;
}

bool identical(const VehicleInputEstimate& a, const VehicleInputEstimate& b) {
  if (a.stamp_s != b.stamp_s || a.valid != b.valid || a.speed_mps != b.speed_mps) return false;
  for (int i = 0; i < kWheelCount; ++i) {
    const WheelInputEstimate &x = a.wheels[static_cast<std::size_t>(i)], &y = b.wheels[static_cast<std::size_t>(i)];
    if (x.load_n != y.load_n || x.slip_ratio != y.slip_ratio || x.slip_angle_rad != y.slip_angle_rad ||
        x.speed_mps != y.speed_mps || x.flags != y.flags)
      return false;
  }
  return true;
}

TEST(VehicleInputPipeline, SpeedRuleIsTheTwistsPlanarNormOrItsLongitudinalComponent) {
  EXPECT_DOUBLE_EQ(referenceSpeed(SpeedRule::kPlanarNorm, 3.0, 4.0), 5.0);
  EXPECT_DOUBLE_EQ(referenceSpeed(SpeedRule::kPlanarNorm, -3.0, 4.0), 5.0);
  EXPECT_DOUBLE_EQ(referenceSpeed(SpeedRule::kLongitudinal, -3.0, 4.0), 3.0);
  SpeedRule rule = SpeedRule::kPlanarNorm;
  EXPECT_TRUE(parseSpeedRule("longitudinal", &rule));
  EXPECT_EQ(rule, SpeedRule::kLongitudinal);
  EXPECT_FALSE(parseSpeedRule("x", &rule));
  EXPECT_STREQ(speedRuleName(SpeedRule::kPlanarNorm), "planar_norm");
}

TEST(VehicleInputPipeline, InputTimeDoesNotDependOnTheOrderTheTopicsArriveIn) {
  // One drive, delivered three times: joints with their IMU sample and odometry 0.05 s after its stamp; joints
  // 0.035 s (3.5 IMU periods) behind the IMU and odometry 0.15 s after its stamp; odometry 0.25 s late, beyond
  // input_delay_s (0.2 s): the cycles wait for it, the result is the same.
  const std::vector<VehicleInputEstimate> a = play(drive(1000.0, 3.0, 1e-6, 0.05));
  const std::vector<VehicleInputEstimate> b = play(drive(1000.0, 3.0, 0.035, 0.15));
  const std::vector<VehicleInputEstimate> c = play(drive(1000.0, 3.0, 1e-6, 0.25));
  ASSERT_EQ(a.size(), 301u);  // 100 Hz over 3 s, both ends
  ASSERT_EQ(b.size(), a.size());
  ASSERT_EQ(c.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(identical(a[k], b[k])) << "cycle " << k;
    EXPECT_TRUE(identical(a[k], c[k])) << "cycle " << k;
  }
  EXPECT_TRUE(a.back().valid);
  EXPECT_EQ(a.back().speed_source, SpeedSource::kWheels);
  EXPECT_NEAR(a.back().speed_mps, 16.5, 0.2);  // 1.2 %: the driven wheels' slip prior under 0.5 m/s^2
}

TEST(VehicleInputPipeline, JointsByNameWithTheirSignsAndAMissingWheelAlone) {
  VehicleInputsConfig c = config();
  c.wheel_velocity_signs = {1.0, -1.0, 1.0, -1.0};  // right-hand joints mirrored
  VehicleInputPipeline pipeline(c);
  const double omega = 10.0 / 0.31;
  // Any order of the names; the front right joint is absent from the later messages.
  const std::vector<std::string> shuffled{"steering_wheel_joint", "wheel_rear_right_joint", "wheel_front_left_joint",
                                          "wheel_rear_left_joint", "wheel_front_right_joint"};
  pipeline.addJoints(0.0, shuffled, {0, 0, 0, 0, 0}, {0.0, -omega, omega, omega, -omega});
  pipeline.addSpeed(0.0, 10.0, 0.0);
  ASSERT_TRUE(pipeline.cycle(0.0));
  EXPECT_EQ(pipeline.estimate().speed_source, SpeedSource::kWheels);
  EXPECT_NEAR(pipeline.estimate().speed_mps, 10.0, 1e-9);
  const std::vector<std::string> three{"wheel_front_left_joint", "wheel_rear_left_joint", "wheel_rear_right_joint",
                                       "steering_wheel_joint"};
  for (int k = 1; k <= 30; ++k) {
    pipeline.addJoints(0.01 * k, three, {0, 0, 0, 0}, {omega, omega, -omega, 0.0});
    ASSERT_TRUE(pipeline.cycle(0.01 * k));
  }
  EXPECT_EQ(pipeline.counters().joints_without_wheels, 30u);
  EXPECT_EQ(pipeline.estimator().faultCount(Sensor::kWheelSpeed, SampleFault::kNotFinite), 30u);
  const WheelInputEstimate& fr = pipeline.estimate().wheels[kFrontRight];
  EXPECT_TRUE(fr.flags & kFlagWheelSpeedMissing);
  EXPECT_TRUE(fr.flags & kFlagSlipRatioFromForce);
  EXPECT_FALSE(pipeline.estimate().wheels[kFrontLeft].flags & kFlagWheelSpeedMissing);
  // Without an IMU mount the loads fall back; the wheel is still publishable, its quality says how.
  EXPECT_TRUE(pipeline.publishable(kFrontRight));
  EXPECT_EQ(pipeline.quality(kFrontRight).slip_ratio_quality, EstimateQuality::kDegraded);
}

TEST(VehicleInputPipeline, WithoutWheelSpeedsEveryWheelGetsItsSlipRatioFromTheForceDemand) {
  VehicleInputsConfig c = config();
  c.use_wheel_speeds = false;
  VehicleInputPipeline pipeline(c);
  ASSERT_TRUE(pipeline.setImuMount({{0.0, 0.0, 0.0, 1.0}}, {{0.0, 0.0, 0.0}}));
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.01 * k;
    pipeline.addImu(t, {{0.0, 0.0, kG}}, {{0.0, 0.0, 0.0}});
    pipeline.addJoints(t, kJoints, {0, 0, 0, 0, 0}, {50.0, 50.0, 50.0, 50.0, 0.0});
    if (k % 10 == 0) pipeline.addSpeed(t, 15.0, 0.0);
    ASSERT_TRUE(pipeline.cycle(t));
  }
  EXPECT_EQ(pipeline.estimate().speed_source, SpeedSource::kReferenceSpeed);
  for (int i = 0; i < kWheelCount; ++i) {
    EXPECT_TRUE(pipeline.publishable(i)) << i;
    EXPECT_TRUE(pipeline.quality(i).flags & kFlagSlipRatioFromForce) << i;
    // Cruising on the flat: the demand is the resistances, a slip ratio of a few 1e-4 at most.
    EXPECT_LT(std::fabs(pipeline.estimate().wheels[static_cast<std::size_t>(i)].slip_ratio), 2e-3) << i;
  }
  EXPECT_EQ(pipeline.estimator().faultCount(Sensor::kWheelSpeed, SampleFault::kNotFinite), 0u);
}

TEST(VehicleInputPipeline, ABadMountIsRefusedAndTheImuWaitsForOne) {
  VehicleInputPipeline pipeline(config());
  EXPECT_FALSE(pipeline.imuMounted());
  EXPECT_FALSE(pipeline.setImuMount({{0.0, 0.0, 0.0, 0.0}}, {{0.0, 0.0, 0.0}}));
  EXPECT_FALSE(pipeline.setImuMount({{kNaN, 0.0, 0.0, 1.0}}, {{0.0, 0.0, 0.0}}));
  EXPECT_FALSE(pipeline.setImuMount({{0.0, 0.0, 0.0, 1.0}}, {{kNaN, 0.0, 0.0}}));
  EXPECT_FALSE(pipeline.imuMounted());
  pipeline.addImu(0.0, {{0.0, 0.0, kG}}, {{0.0, 0.0, 0.0}});
  EXPECT_EQ(pipeline.counters().imu_without_mount, 1u);
  // The mount's translation minus the CoG is the lever arm.
  VehicleInputsConfig c = config();
  c.cog_position_m = {0.1, 0.0, 0.5};
  VehicleInputPipeline mounted(c);
  ASSERT_TRUE(mounted.setImuMount({{0.0, 0.0, 0.0, 1.0}}, {{0.4, -0.2, 0.5}}));
  EXPECT_NEAR(mounted.imuLeverArm_m()[0], 0.3, 1e-12);
  EXPECT_NEAR(mounted.imuLeverArm_m()[1], -0.2, 1e-12);
  EXPECT_NEAR(mounted.imuLeverArm_m()[2], 0.0, 1e-12);
  VehicleInputsConfig bad = config();
  bad.input_delay_s = -0.1;
  EXPECT_THROW(VehicleInputPipeline{bad}, std::invalid_argument);
}

TEST(VehicleInputPipeline, ABackwardClockRestartsTheEstimatorWithItsRadii) {
  VehicleInputsConfig c = config();
  c.input_time = true;
  VehicleInputPipeline pipeline(c);
  std::size_t cycles = 0;
  auto count = [&](double) { ++cycles; };
  for (int k = 0; k <= 100; ++k) {
    pipeline.cyclesBefore(InputStream::kJoints, 100.0 + 0.01 * k, count);
    pipeline.addJoints(100.0 + 0.01 * k, kJoints, {0, 0, 0, 0, 0}, {30.0, 30.0, 30.0, 30.0, 0.0});
  }
  EXPECT_EQ(cycles, 100u);
  // A looped bag: back to 10 s.
  for (int k = 0; k <= 50; ++k) {
    pipeline.cyclesBefore(InputStream::kJoints, 10.0 + 0.01 * k, count);
    pipeline.addJoints(10.0 + 0.01 * k, kJoints, {0, 0, 0, 0, 0}, {30.0, 30.0, 30.0, 30.0, 0.0});
  }
  EXPECT_EQ(pipeline.counters().restarts, 1u);
  EXPECT_EQ(cycles, 150u);
  EXPECT_NEAR(pipeline.estimateTime_s(), 10.49, 1e-9);
  EXPECT_TRUE(pipeline.estimate().valid);
  // On the node's clock, a backward cycle is refused and the next sample restarts.
  VehicleInputPipeline live(config());
  live.addJoints(5.0, kJoints, {0, 0, 0, 0, 0}, {30.0, 30.0, 30.0, 30.0, 0.0});
  EXPECT_TRUE(live.cycle(5.0));
  EXPECT_FALSE(live.cycle(4.0));
  EXPECT_EQ(live.counters().clock_faults, 1u);
  live.addJoints(4.01, kJoints, {0, 0, 0, 0, 0}, {30.0, 30.0, 30.0, 30.0, 0.0});
  EXPECT_EQ(live.counters().restarts, 1u);
  EXPECT_TRUE(live.cycle(4.01));
}

TEST(VehicleInputPipeline, IntakeAndCycleAllocateNothing) {
  VehicleInputsConfig c = config();
  c.input_time = true;
  VehicleInputPipeline pipeline(c);
  ASSERT_TRUE(pipeline.setImuMount({{0.0, 0.0, 0.0, 1.0}}, {{0.0, 0.0, 0.0}}));
  const std::vector<double> position(5, 0.0), velocity{40.0, 40.0, 40.0, 40.0, 0.0};
  pipeline.addJoints(0.0, kJoints, position, velocity);  // the first layout is learned (allocates once)
  int cycles = 0;
  auto count = [&](double) { ++cycles; };
  const long before = t_allocations;
  for (int k = 1; k <= 300; ++k) {
    const double t = 0.01 * k;
    pipeline.cyclesBefore(InputStream::kImu, t, count);
    pipeline.addImu(t, {{0.0, 0.0, kG}}, {{0.0, 0.0, 0.0}});
    pipeline.cyclesBefore(InputStream::kJoints, t, count);
    pipeline.addJoints(t, kJoints, position, velocity);
    if (k % 10 == 0) pipeline.addSpeed(t - 0.1, 12.4, 0.0);
  }
  EXPECT_EQ(t_allocations - before, 0);
  EXPECT_EQ(cycles, 299);  // the grid starts at the first stamp handed to cyclesBefore
}

}  // namespace
}  // namespace tread_wear
