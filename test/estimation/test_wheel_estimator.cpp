// WheelEstimator: input validation, staleness, time jumps and the integration of loss and distance,
// checked against the model evaluated directly (loss = integral of wear per time; constant inputs give
// loss = W_r x distance exactly) and against trapezoid-rule integrals computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Rounding only: the accumulators sum at most a few thousand terms of similar size.
constexpr double kRelTol = 1e-12;

WearModelOptions fastOptions() {
  WearModelOptions o;
  o.preset = Preset::kFast;
  return o;
}

// A Grosch-wheel rig point (paper Table 3 conditions: 75 N, alpha = -2 deg, R_t = 60 mm, 0.15 m/s).
void feed(WheelInputs* in, double t, double load = 75.0, double speed = 0.15) {
  in->setLoad(t, load);
  in->setSlip(t, -2.0 * units::kDegree, 0.0, 1.0 / 0.060);
  in->setSpeed(t, speed);
}

OperatingPoint rigPoint(double load = 75.0, double speed = 0.15) {
  OperatingPoint op;
  op.load_n = load;
  op.speed_mps = speed;
  op.slip_angle_rad = -2.0 * units::kDegree;
  op.path_curvature_per_m = 1.0 / 0.060;
  return op;
}

TEST(InputLimits, ClassifiesEveryFault) {
  InputLimits l;
  EXPECT_EQ(l.checkLoad(kNaN), InputFault::kNotFinite);
  EXPECT_EQ(l.checkLoad(kInf), InputFault::kNotFinite);
  EXPECT_EQ(l.checkLoad(-1.0), InputFault::kNegativeLoad);
  EXPECT_EQ(l.checkLoad(2e5), InputFault::kLoadTooLarge);
  EXPECT_EQ(l.checkLoad(0.0), InputFault::kNone);  // wheel off the ground is valid
  EXPECT_EQ(l.checkSlip(0.0, kNaN, 0.0), InputFault::kNotFinite);
  EXPECT_EQ(l.checkSlip(1.2, 0.0, 0.0), InputFault::kSlipAngleOutOfRange);
  EXPECT_EQ(l.checkSlip(0.0, -1.0, 0.0), InputFault::kSlipRatioOutOfRange);  // locked wheel
  EXPECT_EQ(l.checkSlip(0.0, 5.0, 0.0), InputFault::kSlipRatioOutOfRange);
  EXPECT_EQ(l.checkSlip(0.0, 0.0, 1e3), InputFault::kCurvatureOutOfRange);
  EXPECT_EQ(l.checkSlip(0.1, 0.1, 1.0 / 0.060), InputFault::kNone);
  EXPECT_EQ(l.checkSpeed(-0.1), InputFault::kNegativeSpeed);
  EXPECT_EQ(l.checkSpeed(500.0), InputFault::kSpeedTooLarge);
  EXPECT_EQ(l.checkSpeed(-kInf), InputFault::kNotFinite);
  EXPECT_EQ(l.checkTemperature(1000.0), InputFault::kTemperatureOutOfRange);
  EXPECT_EQ(l.checkTemperature(25.0), InputFault::kNone);
}

TEST(InputLimits, ValidateNamesTheField) {
  InputLimits l;
  l.max_abs_slip_angle_rad = 2.0;
  std::string error;
  ASSERT_FALSE(l.validate(&error));
  EXPECT_NE(error.find("max_abs_slip_angle_rad"), std::string::npos) << error;
  WheelEstimatorParams p;
  p.max_step_s = 0.1;  // below the stale timeout
  ASSERT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("max_step_s"), std::string::npos) << error;
  EXPECT_THROW(WheelEstimator(p, MaterialParams()), std::invalid_argument);
}

TEST(WheelInputs, RejectedSampleInvalidatesAndIsCounted) {
  WheelInputs in;
  EXPECT_EQ(in.setLoad(0.0, 75.0), InputFault::kNone);
  EXPECT_TRUE(in.sample(InputKind::kLoad).valid);
  EXPECT_EQ(in.setLoad(0.1, kNaN), InputFault::kNotFinite);
  EXPECT_EQ(in.setLoad(0.2, -5.0), InputFault::kNegativeLoad);
  EXPECT_FALSE(in.sample(InputKind::kLoad).valid);
  EXPECT_EQ(in.load_n(), 75.0);  // the rejected values were not stored
  EXPECT_EQ(in.sample(InputKind::kLoad).received, 3u);
  EXPECT_EQ(in.sample(InputKind::kLoad).rejected, 2u);
  EXPECT_EQ(in.sample(InputKind::kLoad).last_fault, InputFault::kNegativeLoad);
  EXPECT_EQ(in.faultCount(InputFault::kNotFinite), 1u);
  EXPECT_EQ(in.faultCount(InputFault::kNegativeLoad), 1u);
  EXPECT_EQ(in.totalRejected(), 2u);
  EXPECT_EQ(in.setLoad(0.3, 80.0), InputFault::kNone);
  EXPECT_TRUE(in.sample(InputKind::kLoad).valid);
}

class EstimatorTest : public ::testing::Test {
 protected:
  EstimatorTest() : model_(TireParams(), fastOptions()), est_(WheelEstimatorParams(), MaterialParams()) {}
  WearModel model_;
  WheelEstimator est_;
  WheelInputs in_;
};

TEST_F(EstimatorTest, ConstantInputsGiveLossEqualToWrTimesDistance) {
  WearResult direct;
  ASSERT_EQ(model_.evaluate(rigPoint(), &direct), EvalStatus::kOk);
  const double dt = 0.01;
  const int steps = 500;
  for (int k = 0; k <= steps; ++k) {
    feed(&in_, k * dt);
    const WheelOutput& out = est_.step(k * dt, in_, model_);
    ASSERT_EQ(out.status, WheelStatus::kOk);
    EXPECT_EQ(out.integrated, k > 0);
  }
  const double distance = 0.15 * steps * dt;
  EXPECT_NEAR(est_.output().distance_m, distance, kRelTol * distance);
  const double loss = direct.wear_rate_kg_per_m * distance;
  EXPECT_NEAR(est_.output().accumulated_loss_kg, loss, kRelTol * loss);
  EXPECT_GT(loss, 0.0);
  EXPECT_EQ(est_.unaccountedTime_s(), 0.0);
  EXPECT_EQ(est_.evaluations(), static_cast<std::uint64_t>(steps + 1));
}

TEST_F(EstimatorTest, IrregularStepsUseTheActualElapsedTimeWithTrapezoidRule) {
  // Speed ramps between two values; the trapezoid of wear per time over the actual step lengths.
  const double times[] = {0.0, 0.01, 0.035, 0.04, 0.09, 0.1};
  const double speeds[] = {0.10, 0.12, 0.15, 0.15, 0.20, 0.18};
  double loss = 0.0, distance = 0.0, prev_rate = 0.0;
  for (int k = 0; k < 6; ++k) {
    WearResult r;
    model_.evaluate(rigPoint(75.0, speeds[k]), &r);
    if (k > 0) {
      const double dt = times[k] - times[k - 1];
      loss += 0.5 * (prev_rate + r.wear_rate_kg_per_s) * dt;
      distance += 0.5 * (speeds[k - 1] + speeds[k]) * dt;
    }
    prev_rate = r.wear_rate_kg_per_s;
    feed(&in_, times[k], 75.0, speeds[k]);
    est_.step(times[k], in_, model_);
  }
  EXPECT_NEAR(est_.output().accumulated_loss_kg, loss, kRelTol * loss);
  EXPECT_NEAR(est_.output().distance_m, distance, kRelTol * distance);
}

TEST_F(EstimatorTest, StaleInputIsNotUsedAndTheGapIsUnaccounted) {
  feed(&in_, 0.0);
  est_.step(0.0, in_, model_);
  feed(&in_, 0.1);
  est_.step(0.1, in_, model_);
  const double loss = est_.output().accumulated_loss_kg;
  const std::uint64_t evals = est_.evaluations();
  // No new inputs: at 0.7 s the 0.1 s samples are 0.6 s old > 0.5 s timeout.
  const WheelOutput& out = est_.step(0.7, in_, model_);
  EXPECT_EQ(out.status, WheelStatus::kStaleInput);
  EXPECT_FALSE(out.evaluated);
  EXPECT_EQ(est_.evaluations(), evals);
  EXPECT_EQ(out.accumulated_loss_kg, loss);
  EXPECT_EQ(est_.staleSteps(), 1u);
  // Fresh inputs again: the first fresh step only opens a new interval.
  feed(&in_, 0.8);
  EXPECT_FALSE(est_.step(0.8, in_, model_).integrated);
  feed(&in_, 0.9);
  EXPECT_TRUE(est_.step(0.9, in_, model_).integrated);
  EXPECT_NEAR(est_.unaccountedTime_s(), 0.7, 1e-12);  // (0.1, 0.8]
  // All of it to the stale input, (0.7, 0.8] included: the step at 0.7 s left no usable interval start.
  EXPECT_NEAR(est_.unaccountedTime_s(WheelStatus::kStaleInput), 0.7, 1e-12);
  EXPECT_NEAR(est_.integratedTime_s(), 0.2, 1e-12);  // (0, 0.1] and (0.8, 0.9]
}

TEST_F(EstimatorTest, EveryElapsedSecondIsEitherIntegratedOrLostToItsCause) {
  // 0 to 1 s fresh; 1.0 to 1.3 s invalid load; fresh again; a 5 s forward jump; 0.8 s without a new sample.
  double t = 0.0;
  for (; t < 1.0 - 1e-9; t += 0.1) {
    feed(&in_, t);
    est_.step(t, in_, model_);
  }
  in_.setLoad(1.0, kNaN);
  for (; t < 1.3 - 1e-9; t += 0.1) est_.step(t, in_, model_);
  for (; t < 2.0 - 1e-9; t += 0.1) {
    feed(&in_, t);
    est_.step(t, in_, model_);
  }
  feed(&in_, 7.0);
  EXPECT_EQ(est_.step(7.0, in_, model_).status, WheelStatus::kTimeJump);
  feed(&in_, 7.1);
  est_.step(7.1, in_, model_);
  EXPECT_EQ(est_.step(7.9, in_, model_).status, WheelStatus::kStaleInput);
  // Invalid from the step at 1.0 s to the first fresh one at 1.3 s, plus the interval that step closes: 0.4 s.
  EXPECT_NEAR(est_.unaccountedTime_s(WheelStatus::kInvalidInput), 0.4, 1e-9);
  EXPECT_NEAR(est_.unaccountedTime_s(WheelStatus::kTimeJump), 7.0 - 1.9, 1e-9);
  EXPECT_NEAR(est_.unaccountedTime_s(WheelStatus::kStaleInput), 0.8, 1e-9);
  EXPECT_EQ(est_.unaccountedTime_s(WheelStatus::kNoInput), 0.0);
  EXPECT_EQ(est_.unaccountedTime_s(WheelStatus::kOk), 0.0);
  EXPECT_NEAR(est_.unaccountedTime_s(), 0.4 + 5.1 + 0.8, 1e-9);
  EXPECT_NEAR(est_.integratedTime_s() + est_.unaccountedTime_s(), 7.9, 1e-9);
}

TEST_F(EstimatorTest, InvalidInputNeverReachesTheModel) {
  feed(&in_, 0.0);
  est_.step(0.0, in_, model_);
  const double loss0 = est_.output().accumulated_loss_kg;
  in_.setLoad(0.01, kNaN);
  const WheelOutput& out = est_.step(0.01, in_, model_);
  EXPECT_EQ(out.status, WheelStatus::kInvalidInput);
  EXPECT_FALSE(out.evaluated);
  EXPECT_EQ(out.accumulated_loss_kg, loss0);
  in_.setLoad(0.02, -10.0);
  EXPECT_EQ(est_.step(0.02, in_, model_).status, WheelStatus::kInvalidInput);
  EXPECT_EQ(in_.faultCount(InputFault::kNotFinite), 1u);
  EXPECT_EQ(in_.faultCount(InputFault::kNegativeLoad), 1u);
}

TEST_F(EstimatorTest, MissingInputReportsNoInput) {
  in_.setLoad(0.0, 75.0);
  EXPECT_EQ(est_.step(0.0, in_, model_).status, WheelStatus::kNoInput);
  EXPECT_EQ(est_.evaluations(), 0u);
}

TEST_F(EstimatorTest, BackwardAndForwardJumpsKeepTheAccumulatedState) {
  for (int k = 0; k <= 100; ++k) {
    feed(&in_, 10.0 + k * 0.01);
    est_.step(10.0 + k * 0.01, in_, model_);
  }
  const double loss = est_.output().accumulated_loss_kg;
  const double distance = est_.output().distance_m;
  // A looping bag: time goes back to 0 s; inputs restamped at the new time.
  feed(&in_, 0.0);
  const WheelOutput& back = est_.step(0.0, in_, model_);
  EXPECT_EQ(back.status, WheelStatus::kTimeJump);
  EXPECT_EQ(back.accumulated_loss_kg, loss);
  EXPECT_EQ(back.distance_m, distance);
  EXPECT_EQ(est_.backwardJumps(), 1u);
  // Integration resumes from the new time base.
  feed(&in_, 0.01);
  EXPECT_TRUE(est_.step(0.01, in_, model_).integrated);
  const double after = est_.output().accumulated_loss_kg;
  EXPECT_GT(after, loss);
  // A 100 s forward jump with fresh inputs is not integrated as 100 s of driving.
  feed(&in_, 100.01);
  const WheelOutput& fwd = est_.step(100.01, in_, model_);
  EXPECT_EQ(fwd.status, WheelStatus::kTimeJump);
  EXPECT_EQ(fwd.accumulated_loss_kg, after);
  EXPECT_EQ(est_.forwardJumps(), 1u);
  EXPECT_NEAR(est_.unaccountedTime_s(), 100.0, 1e-9);
}

TEST_F(EstimatorTest, InputsStampedInTheFutureAfterABackwardJumpAreStale) {
  feed(&in_, 50.0);
  est_.step(50.0, in_, model_);
  // The clock resets to 0 but the last samples carry 50 s: they must not be used.
  EXPECT_EQ(est_.step(0.0, in_, model_).status, WheelStatus::kTimeJump);
  EXPECT_EQ(est_.step(0.01, in_, model_).status, WheelStatus::kStaleInput);
}

TEST_F(EstimatorTest, ZeroLoadWearsNothingAndStandstillWearsNothingPerTime) {
  for (int k = 0; k <= 10; ++k) {
    feed(&in_, k * 0.01, 0.0, 0.15);
    est_.step(k * 0.01, in_, model_);
  }
  EXPECT_EQ(est_.output().accumulated_loss_kg, 0.0);
  EXPECT_NEAR(est_.output().distance_m, 0.015, 1e-15);
  WheelEstimator still{WheelEstimatorParams(), MaterialParams()};
  WheelInputs in;
  for (int k = 0; k <= 10; ++k) {
    feed(&in, k * 0.01, 75.0, 0.0);
    EXPECT_EQ(still.step(k * 0.01, in, model_).status, WheelStatus::kLowSpeed);
  }
  EXPECT_EQ(still.output().accumulated_loss_kg, 0.0);  // wear per time is W_r V = 0 at V = 0
}

TEST_F(EstimatorTest, TreadDepthFromMaterial) {
  MaterialParams m;  // Grosch wheel: rho 1150 kg/m^3, width 18 mm, radius 36 mm, depth 6 mm
  est_.restore({1e-3, 5.0});
  const double mass_per_depth = 1150.0 * 0.018 * 2.0 * units::kPi * 0.036;  // [kg/m]
  EXPECT_NEAR(est_.output().tread_depth_loss_m, 1e-3 / mass_per_depth, 1e-15);
  EXPECT_NEAR(est_.output().remaining_tread_depth_m, m.tread_depth_m - 1e-3 / mass_per_depth, 1e-15);
  est_.restore({1.0, 5.0});  // more than the whole tread
  EXPECT_EQ(est_.output().remaining_tread_depth_m, 0.0);
  est_.reset();
  EXPECT_EQ(est_.output().accumulated_loss_kg, 0.0);
  EXPECT_EQ(est_.output().remaining_tread_depth_m, m.tread_depth_m);
}

}  // namespace
}  // namespace tread_wear
