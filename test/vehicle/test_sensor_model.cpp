// SensorModel (vehicle/sensor_model.h): the sensors of a drive, against their definitions.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tread_wear/vehicle/sensor_model.h"

namespace tread_wear {
namespace {

constexpr double kDeg = M_PI / 180.0;

SensorModelParams noiseless() {
  SensorModelParams p;
  p.accel_noise_density = p.gyro_noise_density = 0.0;
  p.wheel_speed_noise_rps = p.odometry_noise_mps = 0.0;
  return p;
}

TEST(SensorModel, DefaultsAreTheDocumentedOnes) {
  const SensorModelParams p;
  std::string error;
  EXPECT_TRUE(p.validate(&error)) << error;
  EXPECT_NEAR(p.imu_mount_rpy_rad[0], 1.0 * kDeg, 1e-12);
  EXPECT_NEAR(p.imu_mount_rpy_rad[1], 2.0 * kDeg, 1e-12);
  EXPECT_NEAR(p.imu_mount_rpy_rad[2], 3.0 * kDeg, 1e-12);
  EXPECT_NEAR(p.steering_quantum_rad, 0.1 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(p.steering_ratio, 15.0);
  EXPECT_DOUBLE_EQ(p.odometry_lag_s, 0.1);
}

TEST(SensorModel, ValidateNamesTheField) {
  std::string error;
  SensorModelParams p;
  p.imu_rate_hz = 0.0;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_EQ(error, "imu_rate_hz = 0: must be > 0");
  p = SensorModelParams();
  p.wheel_radius_error[2] = -0.6;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_EQ(error, "wheel_radius_error = -0.6: must be > -0.5");
  p = SensorModelParams();
  p.odometry_lag_s = std::nan("");
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("odometry_lag_s"), std::string::npos);
  EXPECT_THROW(SensorModel(p, 9.81), std::invalid_argument);
}

TEST(SensorModel, QuaternionRoundTripAndRotation) {
  const std::array<double, 3> rpy{{1.0 * kDeg, 2.0 * kDeg, 3.0 * kDeg}};
  const auto back = SensorModel::rpyOf(SensorModel::quaternion(rpy));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], rpy[i], 1e-12);
  // Pure yaw: R maps IMU x to body (cos, sin, 0).
  const auto R = SensorModel::mountRotation({{0.0, 0.0, 0.5}});
  EXPECT_NEAR(R[0], std::cos(0.5), 1e-15);
  EXPECT_NEAR(R[3], std::sin(0.5), 1e-15);
}

TEST(SensorModel, ImuAtRestMeasuresTiltedGravityPlusBias) {
  SensorModelParams p = noiseless();
  SensorModel model(p, 9.81);
  const VehicleModel vehicle{VehicleParams()};
  VehicleState state;
  const VehicleMotion rest{0.0, 0.0, 0.0};
  vehicle.evaluate(rest, &state);
  const ImuReading r = model.imu(rest, state, 0.0);
  const auto R = SensorModel::mountRotation(p.imu_mount_rpy_rad);
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(r.specific_force_mps2[j], R[6 + j] * 9.81 + p.accel_bias_mps2[j], 1e-12);  // R^T (0, 0, g)
    EXPECT_NEAR(r.angular_rate_rps[j], p.gyro_bias_rps[j], 1e-15);
  }
  // Turning: yaw rate v kappa seen through the mount.
  const VehicleMotion turn{20.0, 0.0, 1.0 / 200.0};
  vehicle.evaluate(turn, &state);
  const ImuReading t = model.imu(turn, state, 0.0);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(t.angular_rate_rps[j], R[6 + j] * 0.1 + p.gyro_bias_rps[j], 1e-12);
}

TEST(SensorModel, LeverArmAddsCentripetalAndTangentialTerms) {
  SensorModelParams p = noiseless();
  p.imu_mount_rpy_rad = {{0.0, 0.0, 0.0}};
  p.accel_bias_mps2 = {{0.0, 0.0, 0.0}};
  p.imu_position_m = {{0.5, 0.2, 0.0}};
  SensorModel at_p(p, 9.81);
  p.imu_position_m = {{0.0, 0.0, 0.0}};
  SensorModel at_cog(p, 9.81);
  const VehicleModel vehicle{VehicleParams()};
  VehicleState state;
  const VehicleMotion turn{20.0, 0.0, 1.0 / 200.0};  // r = 0.1 rad/s
  vehicle.evaluate(turn, &state);
  const ImuReading a = at_p.imu(turn, state, 0.3), b = at_cog.imu(turn, state, 0.3);
  EXPECT_NEAR(a.specific_force_mps2[0] - b.specific_force_mps2[0], -0.3 * 0.2 - 0.01 * 0.5, 1e-12);
  EXPECT_NEAR(a.specific_force_mps2[1] - b.specific_force_mps2[1], 0.3 * 0.5 - 0.01 * 0.2, 1e-12);
  EXPECT_NEAR(a.specific_force_mps2[2] - b.specific_force_mps2[2], 0.0, 1e-12);
}

TEST(SensorModel, WheelSpeedsAreQuantisedOnTheTrueRadius) {
  SensorModelParams p = noiseless();
  p.wheel_radius_error = {{0.01, 0.0, -0.01, 0.02}};
  SensorModel model(p, 9.81);
  const VehicleModel vehicle{VehicleParams()};
  VehicleState state;
  vehicle.evaluate({25.0, 0.5, 0.0}, &state);
  const auto omega = model.wheelSpeeds(state);
  for (int i = 0; i < kWheelCount; ++i) {
    const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
    const double exact = w.speed_mps * (1.0 + w.slip_ratio) / (0.305 * (1.0 + p.wheel_radius_error[i]));
    EXPECT_NEAR(omega[i], exact, 0.5 * p.wheel_speed_quantum_rps + 1e-12);
    EXPECT_NEAR(std::remainder(omega[i], p.wheel_speed_quantum_rps), 0.0, 1e-9);
  }
  EXPECT_NEAR(model.trueRadius(3), 0.305 * 1.02, 1e-15);
  vehicle.evaluate({20.0, 0.0, 1.0 / 100.0}, &state);
  EXPECT_NEAR(model.steeringWheelAngle(state), 15.0 * state.steer_angle_rad, 0.5 * p.steering_quantum_rad);
}

TEST(SensorModel, NoiseHasItsDensityAndIsReproducible) {
  const SensorModelParams p;
  SensorModel a(p, 9.81), b(p, 9.81);
  const VehicleModel vehicle{VehicleParams()};
  VehicleState state;
  const VehicleMotion rest{0.0, 0.0, 0.0};
  vehicle.evaluate(rest, &state);
  const double mean = SensorModel::mountRotation(p.imu_mount_rpy_rad)[6] * 9.81 + p.accel_bias_mps2[0];
  double sum_sq = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const ImuReading ra = a.imu(rest, state, 0.0), rb = b.imu(rest, state, 0.0);
    EXPECT_EQ(ra.specific_force_mps2[0], rb.specific_force_mps2[0]);
    sum_sq += std::pow(ra.specific_force_mps2[0] - mean, 2);
  }
  const double sigma = p.accel_noise_density * std::sqrt(p.imu_rate_hz);  // 0.03 m/s^2
  EXPECT_NEAR(std::sqrt(sum_sq / n), sigma, 0.03 * sigma);
  EXPECT_NEAR(a.odometrySpeed({10.0, 0.0, 0.0}), 10.0, 5 * p.odometry_noise_mps);
  EXPECT_EQ(a.odometrySpeed({0.0, 0.0, 0.0}), 0.0);
}

}  // namespace
}  // namespace tread_wear
