// The vehicle model on a grade and a bank (vehicle_model.h): balances along and normal to the road written out
// independently of the implementation's algebra, and the flat road as the grade-zero case.
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {
namespace {

// Balances are sums of a few doubles of order 1e4 N: round-off far below 1e-6 N.
constexpr double kForceTol_n = 1e-6;

TEST(VehicleModelGrade, BalancesAlongAndNormalToTheRoad) {
  const VehicleParams p;
  const VehicleModel model(p);
  const double m = p.mass_kg, g = p.gravity_mps2, L = p.wheelbase_m, h = p.cog_height_m;
  for (double theta : {0.08, -0.08, 0.3}) {
    const double v = 20.0, a_x = 0.5;
    VehicleState s;
    model.evaluate({v, a_x, 0.0, theta}, &s);
    const double f_aero = 0.5 * p.air_density_kg_per_m3 * p.drag_coefficient * p.frontal_area_m2 * v * v;
    // Normal to the road the wheels carry the weight's normal component.
    double load = 0.0, fx = 0.0;
    for (const WheelState& w : s.wheels) {
      load += w.load_n;
      fx += w.fx_demand_n;
    }
    EXPECT_NEAR(load, m * g * std::cos(theta), kForceTol_n) << theta;
    // Along the road the tires push the car against inertia, drag and the weight's component (rolling resistance is
    // the tires' own: the wheels' demands are net of it).
    EXPECT_NEAR(fx, m * a_x + f_aero + m * g * std::sin(theta), kForceTol_n) << theta;
    // Pitch moment about the rear contact line: front axle load x L = weight normal x l_r - (inertia + drag +
    // weight along the road) x h.
    const double front = s.wheels[kFrontLeft].load_n + s.wheels[kFrontRight].load_n;
    EXPECT_NEAR(front * L,
                m * g * std::cos(theta) * p.cogToRearAxle_m() - (m * a_x + f_aero + m * g * std::sin(theta)) * h,
                kForceTol_n * L)
        << theta;
  }
}

TEST(VehicleModelGrade, ZeroGradeIsTheFlatRoad) {
  const VehicleModel model{VehicleParams()};
  VehicleState flat, zero;
  model.evaluate({15.0, -1.0, 0.01}, &flat);
  model.evaluate({15.0, -1.0, 0.01, 0.0}, &zero);
  for (int i = 0; i < kWheelCount; ++i) {
    const std::size_t w = static_cast<std::size_t>(i);
    EXPECT_EQ(flat.wheels[w].load_n, zero.wheels[w].load_n);
    EXPECT_EQ(flat.wheels[w].slip_ratio, zero.wheels[w].slip_ratio);
    EXPECT_EQ(flat.wheels[w].slip_angle_rad, zero.wheels[w].slip_angle_rad);
  }
}

TEST(VehicleModelGrade, DeceleratingAtTheGradesRateNeedsOnlyTheResistances) {
  // Uphill at a_x = -g sin(theta) the weight's component supplies the deceleration: the tires need only what drag
  // and rolling resistance (on the smaller normal load) take, as on the flat road at a_x = 0.
  const VehicleParams p;
  const VehicleModel model(p);
  const double theta = 0.1;
  VehicleState grade, flat;
  model.evaluate({20.0, -p.gravity_mps2 * std::sin(theta), 0.0, theta}, &grade);
  model.evaluate({20.0, 0.0, 0.0, 0.0}, &flat);
  const double rolling_flat = p.rolling_resistance_coefficient * p.mass_kg * p.gravity_mps2;
  EXPECT_NEAR(grade.force_demand_n, flat.force_demand_n - rolling_flat * (1.0 - std::cos(theta)), kForceTol_n);
}

TEST(VehicleModelBank, AtTheNeutralSpeedTheTiresCarryNoSideForce) {
  // A turn banked towards its inside, driven at the speed where v^2 kappa = g tan(phi): the road's normal force alone
  // supplies the centripetal force (written from the free-body diagram, not from the implementation's algebra). No
  // side force, no lateral load transfer, no slip angle; the normal loads add up to m g / cos(phi).
  const VehicleParams p;
  const VehicleModel model(p);
  const double phi = 0.3, radius = 100.0, g = p.gravity_mps2;
  const double v = std::sqrt(g * std::tan(phi) * radius);
  VehicleState s;
  model.evaluate({v, 0.0, 1.0 / radius, 0.0, phi}, &s);
  double load = 0.0;
  for (const WheelState& w : s.wheels) {
    load += w.load_n;
    EXPECT_NEAR(w.fy_demand_n, 0.0, kForceTol_n);
  }
  EXPECT_NEAR(load, p.mass_kg * g / std::cos(phi), kForceTol_n);
  EXPECT_NEAR(s.wheels[kFrontLeft].load_n, s.wheels[kFrontRight].load_n, kForceTol_n);
  EXPECT_NEAR(s.wheels[kRearLeft].load_n, s.wheels[kRearRight].load_n, kForceTol_n);
  EXPECT_NEAR(s.wheels[kFrontLeft].slip_angle_rad, 0.0, 1e-12);
}

TEST(VehicleModelBank, OnAStraightTheCrossfallPullsDownhill) {
  // Straight, left edge lower: the tires hold the car against the slope with m g sin(phi) to the right (negative),
  // and the road presses with m g cos(phi).
  const VehicleParams p;
  const VehicleModel model(p);
  const double phi = 0.05;
  VehicleState s;
  model.evaluate({20.0, 0.0, 0.0, 0.0, phi}, &s);
  double fy = 0.0, load = 0.0;
  for (const WheelState& w : s.wheels) {
    fy += w.fy_demand_n;
    load += w.load_n;
  }
  EXPECT_NEAR(fy, -p.mass_kg * p.gravity_mps2 * std::sin(phi), kForceTol_n);
  EXPECT_NEAR(load, p.mass_kg * p.gravity_mps2 * std::cos(phi), kForceTol_n);
}

}  // namespace
}  // namespace tread_wear
