// Quasi-steady vehicle model and route: force and moment balances (independent of the implementation's
// algebra), rigid-body kinematics, mirror symmetry, consistency of the car's slip stiffnesses with its tire's
// brush model, the route's lateral-acceleration limit, and bad parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "tread_wear/io/params_io.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
// Balances are sums of a few doubles of order 1e4 N: round-off far below 1e-6 N.
constexpr double kForceTol_n = 1e-6;

VehicleState evaluate(const VehicleModel& m, double v, double a, double kappa) {
  VehicleState s;
  m.evaluate({v, a, kappa}, &s);
  return s;
}

TEST(VehicleModel, StandstillCarriesTheStaticLoadsOnly) {
  const VehicleParams p;
  const VehicleModel m(p);
  const VehicleState s = evaluate(m, 0.0, 0.0, 0.0);
  double total = 0.0;
  for (const WheelState& w : s.wheels) {
    total += w.load_n;
    EXPECT_EQ(w.slip_angle_rad, 0.0);
    EXPECT_EQ(w.slip_ratio, 0.0);  // no rolling resistance at standstill
    EXPECT_EQ(w.speed_mps, 0.0);
  }
  EXPECT_NEAR(total, p.mass_kg * p.gravity_mps2, kForceTol_n);
  EXPECT_NEAR(s.wheels[kFrontLeft].load_n, 0.5 * p.mass_kg * p.gravity_mps2 * p.cogToRearAxle_m() / p.wheelbase_m,
              kForceTol_n);
}

TEST(VehicleModel, AccelerationTransfersLoadAndBalancesForces) {
  const VehicleParams p;
  const VehicleModel m(p);
  const double v = 20.0, a = 1.5;
  const VehicleState s = evaluate(m, v, a, 0.0);
  const double aero = 0.5 * p.air_density_kg_per_m3 * p.drag_coefficient * p.frontal_area_m2 * v * v;
  // Pitch moment about the CoG: the ground forces m a + F_aero act h below it, so the rear loads up.
  const double front = s.wheels[kFrontLeft].load_n + s.wheels[kFrontRight].load_n;
  const double rear = s.wheels[kRearLeft].load_n + s.wheels[kRearRight].load_n;
  EXPECT_NEAR(front + rear, p.mass_kg * p.gravity_mps2, kForceTol_n);
  EXPECT_NEAR(rear * p.cogToRearAxle_m() - front * p.cog_to_front_axle_m, (p.mass_kg * a + aero) * p.cog_height_m,
              1e-6);
  // Horizontal balance: the tread forces accelerate the car against drag (rolling resistance is internal).
  double fx = 0.0;
  for (const WheelState& w : s.wheels) fx += w.fx_demand_n;
  EXPECT_NEAR(fx, p.mass_kg * a + aero, kForceTol_n);
  // Front-wheel drive: front wheels drive (kappa > 0), rear wheels are towed (small braking slip).
  EXPECT_GT(s.wheels[kFrontLeft].slip_ratio, 0.0);
  EXPECT_LT(s.wheels[kRearLeft].slip_ratio, 0.0);
}

TEST(VehicleModel, BrakingFollowsTheBrakeBalance) {
  VehicleParams p;
  p.drag_coefficient = 0.0;
  p.rolling_resistance_coefficient = 0.0;
  const VehicleModel m(p);
  const VehicleState s = evaluate(m, 15.0, -3.0, 0.0);
  const double total = -3.0 * p.mass_kg;
  EXPECT_NEAR(s.wheels[kFrontLeft].fx_demand_n, 0.5 * p.brake_balance_front * total, kForceTol_n);
  EXPECT_NEAR(s.wheels[kRearRight].fx_demand_n, 0.5 * (1.0 - p.brake_balance_front) * total, kForceTol_n);
  // Slip law kappa/(1+kappa) = Fx/(c_kappa Fz), inverted.
  const WheelState& w = s.wheels[kFrontLeft];
  EXPECT_NEAR(w.slip_ratio / (1.0 + w.slip_ratio), w.fx_demand_n / (p.longitudinal_slip_stiffness * w.load_n), 1e-12);
}

TEST(VehicleModel, SteadyLeftTurnBalancesForcesMomentsAndKinematics) {
  const VehicleParams p;
  const VehicleModel m(p);
  const double v = 12.0, kappa = 1.0 / 50.0;  // a_y = 2.88 m/s^2
  const VehicleState s = evaluate(m, v, 0.0, kappa);
  const double a_y = v * v * kappa;
  EXPECT_DOUBLE_EQ(s.lateral_accel_mps2, a_y);
  // Side forces: sum = m a_y, yaw moment about the CoG = 0.
  const double fy_f = s.wheels[kFrontLeft].fy_demand_n + s.wheels[kFrontRight].fy_demand_n;
  const double fy_r = s.wheels[kRearLeft].fy_demand_n + s.wheels[kRearRight].fy_demand_n;
  EXPECT_NEAR(fy_f + fy_r, p.mass_kg * a_y, kForceTol_n);
  EXPECT_NEAR(fy_f * p.cog_to_front_axle_m - fy_r * p.cogToRearAxle_m(), 0.0, 1e-6);
  // Roll moment: the outer (right) wheels carry m a_y h more, split over the tracks.
  const double roll = (s.wheels[kFrontRight].load_n - s.wheels[kFrontLeft].load_n) * 0.5 * p.track_front_m +
                      (s.wheels[kRearRight].load_n - s.wheels[kRearLeft].load_n) * 0.5 * p.track_rear_m;
  EXPECT_NEAR(roll, p.mass_kg * a_y * p.cog_height_m, 1e-6);
  // ISO signs: a left force needs negative slip angles; the outer wheels run faster.
  for (const WheelState& w : s.wheels) {
    EXPECT_LT(w.slip_angle_rad, 0.0);
    EXPECT_GT(w.path_curvature_per_m, 0.0);
    // Rigid body: every wheel turns at the same yaw rate r = v kappa = V_i kappa_i.
    EXPECT_NEAR(w.speed_mps * w.path_curvature_per_m, v * kappa, 1e-12);
  }
  EXPECT_GT(s.wheels[kFrontRight].speed_mps, s.wheels[kFrontLeft].speed_mps);
  // Linear axle slip: alpha_f = -Fy_f / (c_alpha Fz_f).
  const double fz_f = s.wheels[kFrontLeft].load_n + s.wheels[kFrontRight].load_n;
  EXPECT_NEAR(s.wheels[kFrontLeft].slip_angle_rad, -fy_f / (p.cornering_stiffness_front_per_rad * fz_f), 1e-12);
  // Small-angle single-track steering: delta = L kappa + alpha_r - alpha_f (within the small-angle error).
  const double alpha_r = 0.5 * (s.wheels[kRearLeft].slip_angle_rad + s.wheels[kRearRight].slip_angle_rad);
  const double expected = p.wheelbase_m * kappa + alpha_r - s.wheels[kFrontLeft].slip_angle_rad;
  EXPECT_NEAR(s.steer_angle_rad, expected, 0.01 * std::fabs(expected));
}

TEST(VehicleModel, RightTurnMirrorsLeftTurn) {
  const VehicleModel m{VehicleParams()};
  const VehicleState l = evaluate(m, 10.0, 0.5, 1.0 / 30.0), r = evaluate(m, 10.0, 0.5, -1.0 / 30.0);
  const int mirror[kWheelCount] = {kFrontRight, kFrontLeft, kRearRight, kRearLeft};
  for (int i = 0; i < kWheelCount; ++i) {
    const WheelState &a = l.wheels[i], &b = r.wheels[mirror[i]];
    EXPECT_NEAR(a.load_n, b.load_n, 1e-9);
    EXPECT_NEAR(a.slip_angle_rad, -b.slip_angle_rad, 1e-12);
    EXPECT_NEAR(a.path_curvature_per_m, -b.path_curvature_per_m, 1e-12);
    EXPECT_NEAR(a.slip_ratio, b.slip_ratio, 1e-12);
    EXPECT_NEAR(a.speed_mps, b.speed_mps, 1e-12);
  }
}

TEST(VehicleModel, BelowIdealAckermannTheFrontTyresScrubAgainstEachOther) {
  // Creeping round a tight left turn (CoG radius R = 5.85 m, the LEON-T turnovers at full lock): the slip angles are
  // ~1e-5 rad, so the instant centre lies on the rear axle line at R_r = sqrt(R^2 - l_r^2) from its centre and the
  // front wheels' ideal steer angles are atan(L / (R_r -+ t_f/2)) (geometry, not the model's algebra). With
  // Ackermann share A each front wheel steers to the mean plus A times its ideal deviation, so its slip angle is
  // (1 - A) times that deviation: the inner wheel positive (pushed outwards), the outer one negative.
  VehicleParams p;
  const double radius_m = 5.85, v = 0.1;
  const double r_rear = std::sqrt(radius_m * radius_m - p.cogToRearAxle_m() * p.cogToRearAxle_m());
  const double inner = std::atan(p.wheelbase_m / (r_rear - 0.5 * p.track_front_m));
  const double outer = std::atan(p.wheelbase_m / (r_rear + 0.5 * p.track_front_m));
  const double half_difference = 0.5 * (inner - outer);  // 0.051 rad for this car
  for (double share : {1.0, 0.5, 0.0}) {
    p.ackermann_share = share;
    const VehicleState s = evaluate(VehicleModel(p), v, 0.0, 1.0 / radius_m);
    EXPECT_NEAR(s.wheels[kFrontLeft].slip_angle_rad, (1.0 - share) * half_difference, 1e-4) << "A = " << share;
    EXPECT_NEAR(s.wheels[kFrontRight].slip_angle_rad, -(1.0 - share) * half_difference, 1e-4) << "A = " << share;
    EXPECT_NEAR(s.steer_angle_rad, 0.5 * (inner + outer), 1e-4);  // the mean steer is the geometry's, whatever A
    EXPECT_NEAR(s.wheels[kRearLeft].slip_angle_rad, 0.0, 1e-4);   // the rear axle is not steered
  }
  p.ackermann_share = 1.5;
  std::string error;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("ackermann_share = 1.5"), std::string::npos) << error;
  const std::string path = ::testing::TempDir() + "vehicle_ackermann.yaml";
  std::ofstream(path) << "ackermann_share: 0.4\n";
  EXPECT_DOUBLE_EQ(loadVehicleParams(path).ackermann_share, 0.4);
}

TEST(VehicleModel, CarSlipStiffnessesMatchTheTireBrushModel) {
  // The car's linear slip estimates must agree with the forces its tire's brush model produces for them.
  const VehicleParams car = loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml");
  const TireParams tire = loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml");
  WearModelOptions options;
  options.preset = Preset::kStandard;
  const WearModel model(tire, options);
  OperatingPoint op;
  op.speed_mps = 1.0;  // slow: the damping term c_y V alpha is < 1 % of the stiffness term
  op.load_n = VehicleModel(car).staticLoad(kFrontLeft);
  op.slip_angle_rad = -0.002;  // small slip: the patch sticks (linear range)
  WearResult r;
  model.evaluate(op, &r);
  // 5 %: damping, the x_e pressure offset and the graded grid each shift the small-slip slope by ~1 %.
  EXPECT_NEAR(r.fy_n / (-op.slip_angle_rad * op.load_n), car.cornering_stiffness_front_per_rad,
              0.05 * car.cornering_stiffness_front_per_rad);
  op.slip_angle_rad = 0.0;
  op.slip_ratio = 0.001;
  model.evaluate(op, &r);
  EXPECT_NEAR(r.fx_n * (1.0 + op.slip_ratio) / (op.slip_ratio * op.load_n), car.longitudinal_slip_stiffness,
              0.05 * car.longitudinal_slip_stiffness);
}

TEST(VehicleModel, InvalidParametersAreNamed) {
  VehicleParams p;
  std::string error;
  p.cog_to_front_axle_m = 3.0;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("cog_to_front_axle_m = 3"), std::string::npos) << error;
  p = VehicleParams();
  p.brake_balance_front = 1.5;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("brake_balance_front"), std::string::npos);
  EXPECT_THROW(VehicleModel{p}, std::invalid_argument);

  const std::string path = ::testing::TempDir() + "vehicle_bad.yaml";
  std::ofstream(path) << "mass_kg: 1000\nwheel_base_m: 2.5\n";
  try {
    loadVehicleParams(path);
    FAIL() << "unknown key accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'wheel_base_m'"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "drive_layout: sideways\n";
  EXPECT_THROW(loadVehicleParams(path), std::runtime_error);
  EXPECT_THROW(loadVehicleParams("/nonexistent/vehicle.yaml"), std::runtime_error);
  DriveLayout layout;
  EXPECT_TRUE(parseDriveLayout("all", &layout));
  EXPECT_EQ(layout, DriveLayout::kAll);
}

TEST(Route, WltcRouteRespectsTheLateralLimitAndIsContinuousAndDeterministic) {
  const SpeedProfile profile = loadSpeedProfile(kSource + "/data/wltc_class3b.csv");
  RouteParams params;
  const Route route = buildRoute(profile, params);
  EXPECT_GE(route.length_m(), profile.totalDistance_m());
  double max_ay = 0.0;
  for (double t = 0.0; t <= profile.endTime_s(); t += 0.02) {
    const double v = profile.speed(t);
    max_ay = std::max(max_ay, std::fabs(v * v * route.curvature(profile.distance(t))));
  }
  EXPECT_LE(max_ay, params.lateral_accel_limit_mps2 * (1.0 + 1e-9));
  EXPECT_GT(max_ay, 0.5 * params.lateral_accel_limit_mps2);  // the limit is actually used
  // Continuity: curvature changes at most by the steepest clothoid slope 3/R^2 over a 0.05 m step.
  const double max_jump = 3.0 / (params.junction_radius_m * params.junction_radius_m) * 0.05 * 1.01;
  for (double s = 0.05; s < route.length_m(); s += 0.05)
    ASSERT_LE(std::fabs(route.curvature(s) - route.curvature(s - 0.05)), max_jump) << s;
  // Each event turns by its declared angle: the integral of curvature over the event.
  for (const RouteEvent& e : route.events()) {
    double heading = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) heading += route.curvature(e.s_start_m + (i + 0.5) * e.length_m / n) * e.length_m / n;
    EXPECT_NEAR(heading, e.angle_rad, 1e-6) << routeEventKindName(e.kind);
  }
  const Route again = buildRoute(profile, params);
  ASSERT_EQ(again.segments().size(), route.segments().size());
  EXPECT_EQ(again.segments().back().s_start_m, route.segments().back().s_start_m);
  int urban = 0, motorway = 0;
  for (const RouteEvent& e : route.events()) {
    urban += e.kind == RouteEventKind::kJunctionTurn || e.kind == RouteEventKind::kRoundabout;
    motorway += e.kind == RouteEventKind::kMotorwayCurve;
  }
  EXPECT_GT(urban, 0);
  EXPECT_GT(motorway, 0);
  params.lateral_accel_limit_mps2 = 0.0;
  EXPECT_THROW(buildRoute(profile, params), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
