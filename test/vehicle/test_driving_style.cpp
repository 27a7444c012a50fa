// Driving styles (vehicle/driving_style.h) on the WLTC class 3b and its route: every style stays inside its envelope
// (a_x, a_y), all styles drive the same route and distance and stand at the profile's stops, an aggressive drive
// takes less time than a calm one, a_x is continuous, and bad envelopes name their field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/vehicle/driving_style.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
// Accelerations are differences of speeds (and distances) of order 10-1e4 over a 1 s window: round-off ~1e-11.
constexpr double kAccelTol_mps2 = 1e-9;

struct Measured {
  double duration_s, distance_m, max_accel, max_decel, max_lateral, max_jerk;
};

/// Samples the drive at 20 Hz: its largest accelerations, jerk (between samples) and a_y = v^2 kappa.
Measured measure(const SpeedTrace& trace) {
  constexpr double kDt = 0.05;
  Measured m{trace.duration_s(), trace.distance_m(), 0.0, 0.0, 0.0, 0.0};
  VehicleMotion prev = trace.at(0.0);
  for (double t = kDt; t <= trace.duration_s(); t += kDt) {
    const VehicleMotion x = trace.at(t);
    m.max_accel = std::max(m.max_accel, x.accel_mps2);
    m.max_decel = std::max(m.max_decel, -x.accel_mps2);
    m.max_lateral = std::max(m.max_lateral, x.speed_mps * x.speed_mps * std::fabs(x.path_curvature_per_m));
    m.max_jerk = std::max(m.max_jerk, std::fabs(x.accel_mps2 - prev.accel_mps2) / kDt);
    prev = x;
  }
  return m;
}

class DrivingStyleOnWltc : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    profile_ = new SpeedProfile(loadSpeedProfile(kSource + "/data/wltc_class3b.csv"));
    route_ = new Route(buildRoute(*profile_, RouteParams()));  // one route, the default lateral limit, for all styles
  }
  static void TearDownTestSuite() {
    delete profile_;
    delete route_;
  }
  static SpeedProfile* profile_;
  static Route* route_;
};
SpeedProfile* DrivingStyleOnWltc::profile_ = nullptr;
Route* DrivingStyleOnWltc::route_ = nullptr;

TEST_F(DrivingStyleOnWltc, StylesStayInsideTheirEnvelopesOnTheSameRoute) {
  double calm_duration = 0.0, aggressive_duration = 0.0;
  for (const char* style : {"calm", "normal", "aggressive"}) {
    DrivingEnvelope envelope;
    ASSERT_TRUE(drivingStyle(style, &envelope));
    const EnvelopeDrive drive = driveWithinEnvelope(*profile_, *route_, envelope);
    const Measured m = measure(drive.trace);
    EXPECT_LE(m.max_accel, envelope.max_accel_mps2 + kAccelTol_mps2) << style;
    EXPECT_LE(m.max_decel, envelope.max_decel_mps2 + kAccelTol_mps2) << style;
    EXPECT_LE(m.max_lateral, envelope.max_lateral_accel_mps2 * (1.0 + 1e-9)) << style;
    // The envelope is used, not just respected: each limit is reached somewhere (within 2 %).
    EXPECT_GT(m.max_accel, 0.98 * envelope.max_accel_mps2) << style;
    EXPECT_GT(m.max_decel, 0.98 * envelope.max_decel_mps2) << style;
    EXPECT_GT(m.max_lateral, 0.98 * envelope.max_lateral_accel_mps2) << style;
    // Continuous a_x: the jerk stays within (a_max + d_max) / tau (plus one sample's rounding).
    EXPECT_LE(m.max_jerk, (envelope.max_accel_mps2 + envelope.max_decel_mps2) / EnvelopeDriveParams().smoothing_s +
                              1e-6)
        << style;
    // The same route, segment for segment, and the profile's distance.
    const std::vector<RouteSegment>& segments = drive.trace.route().segments();
    ASSERT_EQ(segments.size(), route_->segments().size());
    for (std::size_t k = 0; k < segments.size(); ++k) {
      EXPECT_EQ(segments[k].s_start_m, route_->segments()[k].s_start_m);
      EXPECT_EQ(segments[k].kappa_start_per_m, route_->segments()[k].kappa_start_per_m);
      EXPECT_EQ(segments[k].kappa_end_per_m, route_->segments()[k].kappa_end_per_m);
    }
    EXPECT_NEAR(m.distance_m, profile_->totalDistance_m(), 1e-6) << style;
    if (std::string(style) == "calm") calm_duration = m.duration_s;
    if (std::string(style) == "aggressive") aggressive_duration = m.duration_s;
  }
  EXPECT_LT(aggressive_duration, calm_duration);
}

TEST_F(DrivingStyleOnWltc, StandsAtTheProfilesStopsForTheirDwells) {
  // The profile's stops, independently: runs of samples at 0 km/h (9 in the WLTC class 3b), distance and dwell.
  std::vector<std::pair<double, double>> stops;
  const std::vector<double>& t_p = profile_->times_s();
  const std::vector<double>& v_p = profile_->speeds_mps();
  for (std::size_t i = 0; i < v_p.size(); ++i) {
    if (v_p[i] > 0.0) continue;
    std::size_t j = i;
    while (j + 1 < v_p.size() && v_p[j + 1] == 0.0) ++j;
    stops.push_back({profile_->distance(t_p[i]), t_p[j] - t_p[i]});
    i = j;
  }
  ASSERT_EQ(stops.size(), 9u);
  DrivingEnvelope aggressive;
  ASSERT_TRUE(drivingStyle("aggressive", &aggressive));
  const EnvelopeDrive drive = driveWithinEnvelope(*profile_, *route_, aggressive);
  // Where the drive stands still (speed exactly 0: the window of the average lies inside a dwell), how long.
  constexpr double kDt = 0.1;
  const double tau = drive.trace.smoothing_s();
  std::vector<std::pair<double, double>> standing;  // position, duration
  bool was_standing = false;
  for (double t = 0.0; t <= drive.trace.duration_s(); t += kDt) {
    const bool still = drive.trace.at(t).speed_mps == 0.0;
    if (still && !was_standing) standing.push_back({drive.trace.position(t), 0.0});
    if (still) standing.back().second += kDt;
    was_standing = still;
  }
  ASSERT_EQ(standing.size(), stops.size());
  for (std::size_t k = 0; k < stops.size(); ++k) {
    EXPECT_NEAR(standing[k].first, stops[k].first, 1e-6) << "stop " << k;
    // The dwell less the part of the smoothing window that reaches into the moving drive (none at the ends), to
    // the sampling step.
    EXPECT_GE(standing[k].second, stops[k].second - tau - 2 * kDt) << "stop " << k;
    EXPECT_LE(standing[k].second, stops[k].second + 2 * kDt) << "stop " << k;
  }
  // Phases are carried over by distance: in order, tiling the drive to its end.
  ASSERT_EQ(drive.phases.size(), 4u);
  for (std::size_t i = 0; i + 1 < drive.phases.size(); ++i)
    EXPECT_LE(drive.phases[i].end_s, drive.phases[i + 1].start_s);
  EXPECT_NEAR(drive.phases.back().end_s, drive.trace.duration_s(), 1e-6);
}

TEST(DrivingStyle, BadEnvelopesNameTheirField) {
  DrivingEnvelope envelope;
  EXPECT_FALSE(drivingStyle("sporty", &envelope));
  envelope.max_lateral_accel_mps2 = 9.0;
  std::string error;
  EXPECT_FALSE(envelope.validate(&error));
  EXPECT_EQ(error, "max_lateral_accel_mps2 = 9: must be finite, > 0 and <= 8 (0.8 g)");
  envelope = DrivingEnvelope();
  envelope.max_decel_mps2 = 0.0;
  EXPECT_FALSE(envelope.validate(&error));
  EXPECT_EQ(error, "max_decel_mps2 = 0: must be finite, > 0 and <= 8 (0.8 g)");
  const SpeedProfile profile({0, 10, 20}, {0, 10, 0});
  EXPECT_THROW(driveWithinEnvelope(profile, buildRoute(profile, RouteParams()), envelope), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
