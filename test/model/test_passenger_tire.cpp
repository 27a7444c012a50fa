// The passenger tire file (config/tires/passenger_205_55_r16.yaml) is well posed over the drive's envelope:
// steady sliding is stable (the damping exceeds the friction law's velocity weakening at the peak pressure), and
// the marcher's W_r converges under x-grid refinement at the worst condition of the old, ill-posed file
// (Fz 6 kN, alpha 0, kappa -0.2, V 0.5 m/s). The same checks fail for that old file (friction v_m 70.09 mm/s of
// the rig's carborundum disc), so they detect an ill-posed tire file. Background: docs/passenger_tire.md, "Grid convergence".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tread_wear/io/params_io.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
constexpr double kOldVmMps = 0.07009;    // the Grosch wheel's v_m (Table 4) that the old passenger file kept
constexpr double kEnvelopeLoadN = 8000;  // above the drive's largest wheel load (~7 kN)

TireParams passengerTire() { return loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml"); }

TireParams oldPassengerTire() {
  TireParams p = passengerTire();
  p.friction.v_m_mps = kOldVmMps;
  return p;
}

TEST(PassengerTire, SteepestWeakeningMatchesADenseScanOfTheFrictionLaw) {
  // The closed form of maxWeakeningSlope against finite differences of savkoor() on a dense log grid.
  for (double v_m : {kOldVmMps, 0.7}) {
    for (double h : {0.2, 0.42, 1.0}) {
      FrictionParams fp;
      fp.mu_0 = 0.46;
      fp.mu_m = 1.15;
      fp.v_m_mps = v_m;
      fp.h = h;
      const SavkoorFriction f(fp);
      double steepest = 0.0;
      for (int i = 1; i < 200000; ++i) {
        const double v = v_m * std::pow(10.0, 6.0 * i / 200000.0);  // v_m .. 1e6 v_m
        const double dv = 1e-6 * v;
        steepest = std::max(steepest, -(f.savkoor(v + dv) - f.savkoor(v - dv)) / (2.0 * dv));
      }
      // Scan step 6.9e-5 in ln v near a smooth maximum: the sampled maximum is within ~1e-8 relative.
      EXPECT_NEAR(f.maxWeakeningSlope(), steepest, 1e-6 * steepest) << "v_m " << v_m << ", h " << h;
    }
  }
}

TEST(PassengerTire, StabilityMarginOfAManufacturedPatch) {
  // x_e = y_e = 0 and lambda < 1: both shapes peak at the centre, g(0) = A, so p_peak = Fz A_x A_y / (4 a b).
  TireParams p = passengerTire();
  p.footprint.lambda_x = 0.5;
  p.footprint.lambda_y = 0.5;
  p.footprint.x_e_m = 0.0;
  p.footprint.y_e_m = 0.0;
  const double load_n = 5000.0;
  const ContactPatch patch(p.footprint, load_n);
  auto shape_a = [](double n, double lambda) { return (2 * n + 1) * (4 * n + 1) / (2 * n * (4 * n + 1 + lambda)); };
  const double p_peak = load_n * shape_a(p.footprint.n_x, 0.5) * shape_a(p.footprint.n_y, 0.5) /
                        (4.0 * patch.halfLength() * patch.halfWidth());
  const double sat = std::pow(p_peak / p.friction.p_ref_pa, -p.friction.q);
  const double expected = std::min(p.tread.c_x_pa_s_per_m, p.tread.c_y_pa_s_per_m) /
                          (sat * p_peak * SavkoorFriction(p.friction).maxWeakeningSlope());
  // The peak is found by sampling at 4001 points; at the centre the sampling hits it exactly.
  EXPECT_NEAR(slidingStabilityMargin(p, load_n), expected, 1e-9 * expected);
}

TEST(PassengerTire, SteadySlidingIsStableOverTheDriveEnvelope) {
  // The margin falls with load (peak pressure ~ sqrt(Fz)); above 1 at 8 kN means stable at every drive load.
  const TireParams tire = passengerTire();
  EXPECT_GT(slidingStabilityMargin(tire, 2000.0), slidingStabilityMargin(tire, kEnvelopeLoadN));
  EXPECT_GT(slidingStabilityMargin(tire, kEnvelopeLoadN), 1.2) << "20 % margin wanted against load and pressure";
  EXPECT_LT(slidingStabilityMargin(oldPassengerTire(), 2000.0), 1.0) << "the old file is ill-posed at every load";
}

/// W_r [kg/m] of the marcher at the old file's worst condition on an x grid of n steps (8 strips, graded).
double worstCaseWear(const TireParams& tire, int n_x_steps) {
  BrushOptions options;
  options.grid = {n_x_steps, 8, 0.8, LateralRule::kSineMidpoint};
  const BrushWearModel model(tire, options);
  OperatingPoint op;
  op.load_n = 6000.0;
  op.slip_ratio = -0.2;
  op.speed_mps = 0.5;
  WearResult r;
  model.evaluate(op, &r);
  return r.wear_rate_kg_per_m;
}

TEST(PassengerTire, WearConvergesUnderGridRefinementAtTheOldWorstCase) {
  // A well-posed problem on the BDF2 marcher converges at first order or better (second order where smooth;
  // the stick/slide switches are first order), so each halving of the step at least halves the change:
  // |W(2n) - W(n)| <= |W(n) - W(n/2)| / 2 up to a factor for the pre-asymptotic range (here 1.5 instead of 2).
  // The ill-posed file instead grows W_r with refinement (stick-slip cycles resolved ever better).
  for (bool old_file : {false, true}) {
    const TireParams tire = old_file ? oldPassengerTire() : passengerTire();
    const double w200 = worstCaseWear(tire, 200), w400 = worstCaseWear(tire, 400), w800 = worstCaseWear(tire, 800);
    const double change_coarse = std::fabs(w400 / w200 - 1.0), change_fine = std::fabs(w800 / w400 - 1.0);
    const bool converges = change_fine <= change_coarse / 1.5 && change_fine < 0.01;
    EXPECT_EQ(converges, !old_file) << (old_file ? "old" : "new") << " file: W_r " << w200 << ", " << w400 << ", "
                                    << w800 << " kg/m at 200, 400, 800 x-steps";
  }
}

}  // namespace
}  // namespace tread_wear
