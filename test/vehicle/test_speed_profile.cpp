// Speed profiles: PCHIP interpolation against exact references (linear and constant profiles, numerical
// integration), the WLTC class 3b cycle against its published figures, and bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {
namespace {

// Round-off of sums over ~1e3 doubles of order 1e4 [same unit as the checked value].
constexpr double kRoundOff = 1e-9;

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(SpeedProfile, LinearRampIsReproducedExactly) {
  // v = 2 t: PCHIP keeps linear data linear, so a = 2 and s = t^2 exactly.
  const SpeedProfile p({0.0, 1.0, 2.0, 3.0}, {0.0, 2.0, 4.0, 6.0});
  for (double t = 0.0; t <= 3.0; t += 0.05) {
    EXPECT_NEAR(p.speed(t), 2.0 * t, kRoundOff);
    EXPECT_NEAR(p.acceleration(t), 2.0, kRoundOff);
    EXPECT_NEAR(p.distance(t), t * t, kRoundOff);
  }
}

TEST(SpeedProfile, DistanceIsTheIntegralOfSpeedAndAccelerationItsDerivative) {
  const SpeedProfile p({0, 1, 2, 3, 4, 5, 6}, {0, 3, 7, 8, 8, 4, 0});
  // Composite Simpson on a fine grid: error ~ h^4 v'''' , far below 1e-6 m for h = 1e-3 s.
  const int n = 6000;
  const double h = 6.0 / n;
  double s = 0.0;
  for (int i = 0; i < n; i += 2)
    s += h / 3.0 * (p.speed(i * h) + 4.0 * p.speed((i + 1) * h) + p.speed((i + 2) * h));
  EXPECT_NEAR(p.totalDistance_m(), s, 1e-6);
  for (double t = 0.3; t < 6.0; t += 0.37) {
    const double d = 1e-6;  // central difference step [s]; truncation ~ d^2 v''' << 1e-5
    EXPECT_NEAR(p.acceleration(t), (p.speed(t + d) - p.speed(t - d)) / (2 * d), 1e-5) << t;
  }
}

TEST(SpeedProfile, NoOvershootAndAccelerationContinuousAtSamples) {
  // A stop-and-go shape: the interpolant must stay within the samples (never negative, never above the peak).
  const SpeedProfile p({0, 1, 2, 3, 4, 5}, {0, 10, 10.5, 0, 0, 12});
  for (double t = 0.0; t <= 5.0; t += 0.001) {
    EXPECT_GE(p.speed(t), 0.0);
    EXPECT_LE(p.speed(t), 12.0);
  }
  EXPECT_DOUBLE_EQ(p.maxSpeed(0.0, 2.5), 10.5);
  EXPECT_EQ(p.speed(3.5), 0.0);  // flat zero segment stays zero
  for (double t : {1.0, 2.0, 3.0, 4.0}) EXPECT_NEAR(p.acceleration(t - 1e-9), p.acceleration(t + 1e-9), 1e-6) << t;
}

TEST(SpeedProfile, WltcClass3bMatchesThePublishedCycle) {
  const SpeedProfile p = loadSpeedProfile(std::string(TREAD_WEAR_SOURCE_DIR) + "/data/wltc_class3b.csv");
  // UN GTR No. 15: 1800 s, 23.27 km (23 266 m), top speed 131.3 km/h, four phases.
  EXPECT_DOUBLE_EQ(p.duration_s(), 1800.0);
  EXPECT_NEAR(p.totalDistance_m(), 23266.0, 0.001 * 23266.0);  // interpolation vs the 1 Hz trapezoid: < 0.1 %
  EXPECT_NEAR(p.maxSpeed_mps() * 3.6, 131.3, 1e-9);
  ASSERT_EQ(p.phases().size(), 4u);
  EXPECT_EQ(p.phases()[0].name, "Low");
  EXPECT_EQ(p.phases()[3].name, "Extra High");
  EXPECT_EQ(p.phaseAt(589.5), 0);
  EXPECT_EQ(p.phaseAt(590.0), 1);
  EXPECT_EQ(p.phaseAt(1800.0), 3);
  EXPECT_EQ(p.phaseAt(1800.5), -1);
}

TEST(SpeedProfile, AcceptsSpeedInMetresPerSecond) {
  const SpeedProfile p = loadSpeedProfile(writeTemp("mps.csv", "time_s,speed_mps\n0,0\n10,10\n"));
  EXPECT_NEAR(p.totalDistance_m(), 50.0, kRoundOff);
}

TEST(SpeedProfile, BadFilesNameTheProblem) {
  auto message = [](const std::string& text) {
    try {
      loadSpeedProfile(writeTemp("bad.csv", text));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("time_s,speed\n0,1\n1,2\n").find("speed_kmh or speed_mps"), std::string::npos);
  EXPECT_NE(message("time_s,speed_kmh\n0,1\n0,2\n").find("does not increase"), std::string::npos);
  EXPECT_NE(message("time_s,speed_kmh\n0,1\n1,-2\n").find("negative speed"), std::string::npos);
  EXPECT_NE(message("time_s,speed_kmh\n0,1\n1,nan\n").find(":3:"), std::string::npos);
  EXPECT_NE(message("time_s,speed_kmh\n0,1\n").find("at least 2"), std::string::npos);
  EXPECT_NE(message("# Phases: Low 0-x\ntime_s,speed_kmh\n0,1\n1,1\n").find("Low 0-x"), std::string::npos);
  EXPECT_THROW(loadSpeedProfile("/nonexistent/profile.csv"), std::runtime_error);
  EXPECT_THROW(SpeedProfile({0.0, 1.0}, {0.0}), std::invalid_argument);
}

TEST(SpeedProfile, PhaseListParsing) {
  std::vector<ProfilePhase> phases;
  std::string error;
  ASSERT_TRUE(parsePhaseList(" Low 0-589, Extra High 1478-1800", &phases, &error)) << error;
  EXPECT_EQ(phases[1].name, "Extra High");
  EXPECT_DOUBLE_EQ(phases[1].start_s, 1478.0);
  EXPECT_FALSE(parsePhaseList("Low 10-5", &phases, &error));
  EXPECT_FALSE(parsePhaseList("Low 0-10, Mid 5-20", &phases, &error));
  EXPECT_NE(error.find("before the previous phase ends"), std::string::npos);
}

}  // namespace
}  // namespace tread_wear
