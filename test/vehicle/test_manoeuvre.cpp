// Test manoeuvres (vehicle/manoeuvre.h) and the speed trace under them (vehicle/drive_motion.h): the cruise and the
// circle hold the analytic steady state of vehicle_model.h from their first sample, the accel cycles stay inside
// their accelerations with a continuous a_x, a mass override scales the static loads exactly, and bad settings name
// their field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tread_wear/vehicle/manoeuvre.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {
namespace {

// Loads are a few doubles of order 1e3-1e4 N combined: round-off far below 1e-6 N.
constexpr double kForceTol_n = 1e-6;
// Speeds and accelerations from differences of distances of order 1e3 m over a 1 s window: round-off ~1e-12.
constexpr double kKinematicTol = 1e-9;

ManoeuvreParams cruise(double speed_kmh, double duration_s) {
  ManoeuvreParams p;
  p.kind = Manoeuvre::kCruise;
  p.speed_mps = speed_kmh / 3.6;
  p.duration_s = duration_s;
  return p;
}

TEST(Manoeuvre, CruiseHoldsStaticLoadsPlusAeroTransfer) {
  const VehicleParams car;
  const VehicleModel model(car);
  const ManoeuvreParams params = cruise(100.0, 30.0);
  const SpeedTrace trace = buildManoeuvre(params);
  const double v = params.speed_mps;
  EXPECT_DOUBLE_EQ(trace.duration_s(), 30.0);
  EXPECT_NEAR(trace.distance_m(), v * 30.0, 1e-9);
  // Analytic: drag at CoG height moves F_aero h / L from the front axle to the rear, split equally left/right.
  const double aero = 0.5 * car.air_density_kg_per_m3 * car.drag_coefficient * car.frontal_area_m2 * v * v;
  const double transfer = aero * car.cog_height_m / car.wheelbase_m / 2.0;
  const double expected[kWheelCount] = {model.staticLoad(kFrontLeft) - transfer, model.staticLoad(kFrontRight) - transfer,
                                        model.staticLoad(kRearLeft) + transfer, model.staticLoad(kRearRight) + transfer};
  for (double t = 0.0; t <= 30.0; t += 0.25) {
    const VehicleMotion m = trace.at(t);
    EXPECT_EQ(m.speed_mps, v) << t;  // from the first sample: no run-up
    EXPECT_EQ(m.accel_mps2, 0.0) << t;
    EXPECT_EQ(m.path_curvature_per_m, 0.0) << t;
    VehicleState s;
    model.evaluate(m, &s);
    EXPECT_EQ(s.lateral_accel_mps2, 0.0);
    for (int w = 0; w < kWheelCount; ++w) EXPECT_NEAR(s.wheels[w].load_n, expected[w], kForceTol_n) << wheelName(w);
  }
}

TEST(Manoeuvre, CircleHoldsItsLateralAccelerationAndLoadTransfer) {
  const VehicleParams car;
  const VehicleModel model(car);
  for (const bool right : {false, true}) {
    ManoeuvreParams params;
    params.kind = Manoeuvre::kCircle;
    params.speed_mps = 60.0 / 3.6;
    params.lateral_accel_mps2 = 4.0;
    params.turn_right = right;
    params.duration_s = 20.0;
    const SpeedTrace trace = buildManoeuvre(params);
    const double v = params.speed_mps, a_y = right ? -4.0 : 4.0, radius = v * v / 4.0;
    EXPECT_NEAR(params.circleRadius_m(), radius, 1e-12);
    const double aero = 0.5 * car.air_density_kg_per_m3 * car.drag_coefficient * car.frontal_area_m2 * v * v;
    const double dfz_long = aero * car.cog_height_m / car.wheelbase_m;
    // vehicle_model.h: dFz_f = m a_y h lambda_f / t_f, dFz_r = m a_y h (1 - lambda_f) / t_r; outer wheels gain it.
    const double dfz_f = car.mass_kg * a_y * car.cog_height_m * car.front_roll_stiffness_share / car.track_front_m;
    const double dfz_r =
        car.mass_kg * a_y * car.cog_height_m * (1.0 - car.front_roll_stiffness_share) / car.track_rear_m;
    const double front = model.staticLoad(kFrontLeft) - dfz_long / 2.0;
    const double rear = model.staticLoad(kRearLeft) + dfz_long / 2.0;
    const double expected[kWheelCount] = {front - dfz_f, front + dfz_f, rear - dfz_r, rear + dfz_r};
    for (double t = 0.0; t <= 20.0; t += 0.25) {
      const VehicleMotion m = trace.at(t);
      EXPECT_EQ(m.speed_mps, v);
      EXPECT_EQ(m.accel_mps2, 0.0);
      EXPECT_NEAR(m.path_curvature_per_m, (right ? -1.0 : 1.0) / radius, 1e-15) << t;  // entered at steady state
      VehicleState s;
      model.evaluate(m, &s);
      EXPECT_NEAR(s.lateral_accel_mps2, a_y, 1e-12);
      for (int w = 0; w < kWheelCount; ++w) EXPECT_NEAR(s.wheels[w].load_n, expected[w], kForceTol_n) << wheelName(w);
    }
  }
}

TEST(Manoeuvre, AccelCyclesStayWithinTheirAccelerationsWithContinuousAx) {
  ManoeuvreParams params;
  params.kind = Manoeuvre::kAccelCycles;
  params.low_speed_mps = 30.0 / 3.6;
  params.high_speed_mps = 80.0 / 3.6;
  params.accel_mps2 = 2.0;
  params.decel_mps2 = 3.0;
  params.duration_s = 60.0;
  const SpeedTrace trace = buildManoeuvre(params);
  const double dt = 0.01;
  double max_a = 0.0, min_a = 0.0, max_jerk = 0.0, v_min = 1e9, v_max = 0.0;
  VehicleMotion prev = trace.at(0.0);
  EXPECT_NEAR(prev.speed_mps, params.low_speed_mps, kKinematicTol);  // starts in steady cruise at v_low
  EXPECT_NEAR(prev.accel_mps2, 0.0, kKinematicTol);
  for (double t = dt; t <= 60.0; t += dt) {
    const VehicleMotion m = trace.at(t);
    max_a = std::max(max_a, m.accel_mps2);
    min_a = std::min(min_a, m.accel_mps2);
    max_jerk = std::max(max_jerk, std::fabs(m.accel_mps2 - prev.accel_mps2) / dt);
    v_min = std::min(v_min, m.speed_mps);
    v_max = std::max(v_max, m.speed_mps);
    // a_x is the derivative of the speed: the trapezoid rule over dt is exact where a_x is linear and off by at most
    // dt times the jerk bound (a + d) / tau where a_x has a kink.
    EXPECT_NEAR((m.speed_mps - prev.speed_mps) / dt, 0.5 * (m.accel_mps2 + prev.accel_mps2), dt * 5.0) << t;
    EXPECT_EQ(m.path_curvature_per_m, 0.0);
    prev = m;
  }
  // Each phase holds its acceleration (the 7-4.6 s phases are longer than the 1 s smoothing) and never exceeds it.
  EXPECT_NEAR(max_a, 2.0, kKinematicTol);
  EXPECT_NEAR(min_a, -3.0, kKinematicTol);
  EXPECT_LE(max_a, 2.0 + kKinematicTol);
  EXPECT_GE(min_a, -3.0 - kKinematicTol);
  // Bounded jerk: (a + d) / tau at most.
  EXPECT_LE(max_jerk, (2.0 + 3.0) / kAccelCycleSmoothing_s + 1e-6);
  EXPECT_GE(v_min, params.low_speed_mps - 0.5);  // the smoothing rounds the turning points by < a tau / 8
  EXPECT_LE(v_max, params.high_speed_mps);
}

TEST(Manoeuvre, MassOverrideScalesTheStaticLoadsExactly) {
  VehicleParams car;
  const VehicleModel base(car);
  car.mass_kg *= 1.25;
  const VehicleModel heavy(car);
  for (int w = 0; w < kWheelCount; ++w)
    EXPECT_NEAR(heavy.staticLoad(w), 1.25 * base.staticLoad(w), 1e-9) << wheelName(w);
  VehicleState s;
  heavy.evaluate({0.0, 0.0, 0.0}, &s);
  for (int w = 0; w < kWheelCount; ++w) EXPECT_NEAR(s.wheels[w].load_n, heavy.staticLoad(w), kForceTol_n);
}

TEST(Manoeuvre, BadSettingsNameTheirField) {
  struct Case {
    ManoeuvreParams params;
    const char* message;
  };
  ManoeuvreParams negative_speed = cruise(-10.0, 10.0);
  ManoeuvreParams zero_duration = cruise(50.0, 0.0);
  ManoeuvreParams hard_circle;
  hard_circle.kind = Manoeuvre::kCircle;
  hard_circle.lateral_accel_mps2 = 12.0;
  ManoeuvreParams inverted;
  inverted.kind = Manoeuvre::kAccelCycles;
  inverted.high_speed_mps = inverted.low_speed_mps;
  ManoeuvreParams no_brake;
  no_brake.kind = Manoeuvre::kAccelCycles;
  no_brake.decel_mps2 = -3.0;
  const Case cases[] = {{negative_speed, "speed_mps = -2.777777778: must be finite and > 0"},
                        {zero_duration, "duration_s = 0: must be finite and > 0"},
                        {hard_circle, "lateral_accel_mps2 = 12: must be finite, > 0 and <= 8 (0.8 g)"},
                        {inverted, "high_speed_mps = 8.333333333: must be finite and > low_speed_mps"},
                        {no_brake, "decel_mps2 = -3: must be finite, > 0 and <= 8 (0.8 g)"}};
  for (const Case& c : cases) {
    std::string error;
    EXPECT_FALSE(c.params.validate(&error));
    EXPECT_EQ(error, c.message);
    EXPECT_THROW(buildManoeuvre(c.params), std::invalid_argument);
  }
  ManoeuvreParams profile;
  profile.kind = Manoeuvre::kProfile;
  EXPECT_THROW(buildManoeuvre(profile), std::invalid_argument);
  Manoeuvre parsed;
  EXPECT_FALSE(parseManoeuvre("drift", &parsed));
  ASSERT_TRUE(parseManoeuvre("accel", &parsed));
  EXPECT_EQ(parsed, Manoeuvre::kAccelCycles);
}

}  // namespace
}  // namespace tread_wear
