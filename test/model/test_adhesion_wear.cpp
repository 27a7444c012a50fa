// The adhesion-zone term (model/adhesion_wear.h) against its closed forms: the free-rolling tread-band shear energy
// 2 (2b) k_x delta_max^2 with delta_max = 2 a^3 / (9 sqrt(3) r_l r_e), independent of speed; the small-slip limit
// k_x (2 a sigma)^2 / 2 per unit width (the exit energy of a linear brush in full stick); the brush model's W_r
// gains exactly W_a and nothing else; the term off leaves the paper's model bit for bit; bad input gives zero.
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/io/params_io.h"
#include "tread_wear/model/adhesion_wear.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;

/// The road tire with the term on at 1 mg/kJ and friction high enough that the whole patch adheres at the slips
/// used, so that the closed forms (full adhesion) apply.
TireParams adheringTire() {
  TireParams p = loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml");
  p.wear.adhesion_kg_per_j = 1.0 * units::kMilligramPerKilojoule;
  p.friction.mu_0 = 50.0;
  p.friction.mu_m = 60.0;
  return p;
}

AdhesionWearResult adhesion(const TireParams& p, const OperatingPoint& op) {
  const ContactPatch patch(p.footprint, op.load_n);
  return AdhesionWear(p).evaluate(op, patch, op.tipKinematics(TurnSlipOrientation::kLiteral), op.rollingSpeed());
}

TEST(AdhesionWear, FreeRollingShearEnergyMatchesTheClosedFormAtAnySpeed) {
  const TireParams p = adheringTire();
  for (double load : {2000.0, 4000.0, 7000.0}) {
    const ContactPatch patch(p.footprint, load);
    const double a = patch.halfLength(), b = patch.halfWidth(), r0 = p.material.rolling_radius_m;
    const double r_l = r0 - a * a / (2.0 * r0), r_e = r_l + a * a / (3.0 * r_l);  // zero net force
    EXPECT_NEAR(r_e, r0 - (r0 - r_l) / 3.0, 1e-3 * r0);                           // the textbook r_e = r_0 - rho/3
    const double delta_max = 2.0 * a * a * a / (9.0 * std::sqrt(3.0) * r_l * r_e);
    const double expected = 2.0 * (2.0 * b) * p.tread.longitudinalStiffness(load) * delta_max * delta_max;
    for (double speed : {5.0, 30.0}) {
      OperatingPoint op;
      op.speed_mps = speed;
      op.load_n = load;
      const AdhesionWearResult r = adhesion(p, op);
      EXPECT_NEAR(r.free_rolling_shear_m, delta_max, 1e-12) << load;
      // Total variation between 41 nodes: exact but at the four extrema, within 1 %.
      EXPECT_NEAR(r.work_j_per_m, expected, 0.01 * expected) << load << " N, " << speed << " m/s";
      EXPECT_NEAR(r.wear_kg_per_m, r.work_j_per_m * 1e-9, 1e-12 * r.work_j_per_m);
    }
  }
}

TEST(AdhesionWear, SmallSlipGivesTheLinearBrushExitEnergy) {
  TireParams p = adheringTire();
  p.material.rolling_radius_m = 1e4;  // a huge wheel: no tread-band shear
  const double load = 4000.0, speed = 20.0;
  const ContactPatch patch(p.footprint, load);
  const double a = patch.halfLength(), b = patch.halfWidth();
  for (double kappa : {0.002, -0.004}) {
    OperatingPoint op;
    op.speed_mps = speed;
    op.load_n = load;
    op.slip_ratio = kappa;
    const double sigma = op.tipKinematics(TurnSlipOrientation::kLiteral).v_rx0_mps / op.rollingSpeed();
    const double k = p.tread.longitudinalStiffness(load);
    // Per unit width k (2 a sigma)^2 / 2 at the exit, times the width 2b and V_r/V per distance of the centre.
    const double expected = 0.5 * k * std::pow(2.0 * a * sigma, 2) * 2.0 * b * op.rollingSpeed() / speed;
    EXPECT_NEAR(adhesion(p, op).work_j_per_m, expected, 0.01 * expected) << kappa;
  }
  // Lateral: the same with k_y and sigma_y = -sin(alpha) V / V_r.
  OperatingPoint op;
  op.speed_mps = speed;
  op.load_n = load;
  op.slip_angle_rad = 0.003;
  const double sigma = op.tipKinematics(TurnSlipOrientation::kLiteral).v_ry0_mps / op.rollingSpeed();
  const double expected =
      0.5 * p.tread.lateralStiffness(load) * std::pow(2.0 * a * sigma, 2) * 2.0 * b * op.rollingSpeed() / speed;
  EXPECT_NEAR(adhesion(p, op).work_j_per_m, expected, 0.01 * expected);
}

TEST(AdhesionWear, BrushModelAddsExactlyTheAdhesionWear) {
  TireParams on = loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml");
  on.wear.adhesion_kg_per_j = 5.0 * units::kMilligramPerKilojoule;
  TireParams off = on;
  off.wear.adhesion_kg_per_j = 0.0;
  const BrushOptions options;
  const BrushWearModel with(on, options), without(off, options);
  OperatingPoint op;
  op.speed_mps = 25.0;
  op.load_n = 4500.0;
  op.slip_angle_rad = -0.02;
  op.slip_ratio = 0.01;
  WearResult r_on, r_off;
  with.evaluate(op, &r_on);
  without.evaluate(op, &r_off);
  const double w_a = adhesion(on, op).wear_kg_per_m;
  EXPECT_GT(w_a, 0.0);
  EXPECT_NEAR(r_on.wear_rate_kg_per_m, r_off.wear_rate_kg_per_m + w_a, 1e-12 * r_on.wear_rate_kg_per_m);
  EXPECT_NEAR(r_on.wear_rate_kg_per_s, r_on.wear_rate_kg_per_m * op.speed_mps, 1e-12 * r_on.wear_rate_kg_per_s);
  EXPECT_EQ(r_on.fx_n, r_off.fx_n);  // forces are the brush's alone
  EXPECT_EQ(r_on.fy_n, r_off.fy_n);
  // Free rolling wears now; before, exactly nothing.
  op.slip_angle_rad = 0.0;
  op.slip_ratio = 0.0;
  with.evaluate(op, &r_on);
  without.evaluate(op, &r_off);
  EXPECT_EQ(r_off.wear_rate_kg_per_m, 0.0);
  EXPECT_GT(r_on.wear_rate_kg_per_m, 0.0);
}

TEST(AdhesionWear, OffWhenTheCoefficientIsZeroAndZeroWithoutRolling) {
  TireParams p = adheringTire();
  p.wear.adhesion_kg_per_j = 0.0;
  OperatingPoint op;
  op.speed_mps = 20.0;
  op.load_n = 4000.0;
  op.slip_ratio = 0.01;
  EXPECT_TRUE(AdhesionWear(p).off());
  EXPECT_EQ(adhesion(p, op).work_j_per_m, 0.0);
  const TireParams q = adheringTire();
  const ContactPatch patch(q.footprint, 4000.0);
  EXPECT_EQ(AdhesionWear(q).evaluate(op, patch, op.tipKinematics(TurnSlipOrientation::kLiteral), 0.0).wear_kg_per_m,
            0.0);
  p.wear.adhesion_kg_per_j = -1.0;
  std::string error;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("wear.adhesion"), std::string::npos) << error;
}

}  // namespace
}  // namespace tread_wear
