// InputTimeline: samples that arrive out of order across inputs, in bursts or late are stepped exactly as the offline
// replay (DriveReplay, an independent loop over the same samples in stamp order) steps them; an input that stops is
// given up after the documented lead and wait and its time is lost, counted, never held silently.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/estimation/input_timeline.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

constexpr double kRate_hz = 20.0;          // the wheel's step rate
constexpr double kSamplePeriod_s = 0.02;   // 50 Hz inputs, as the drive bags
// Rounding only: the two loops sum the same terms; their step times differ in the last bit (k / rate vs k step).
constexpr double kRelTol = 1e-12;

WearModelOptions fastOptions() {
  WearModelOptions o;
  o.preset = Preset::kFast;
  return o;
}

/// Grosch-rig inputs that vary within a step (so that a sample applied one step late changes the wear): load,
/// slip angle and speed oscillate at different periods. k-th sample of `kind`, stamped at t0 + k period.
InputSample rigSample(InputKind kind, int k) {
  const double t = 100.0 + kSamplePeriod_s * k;
  InputSample s;
  s.t_s = t;
  s.kind = kind;
  switch (kind) {
    case InputKind::kLoad: s.value[0] = 75.0 + 20.0 * std::sin(3.1 * t); break;
    case InputKind::kSlip:
      s.value[0] = (-2.0 + 1.5 * std::sin(2.3 * t)) * units::kDegree;
      s.value[2] = 1.0 / 0.060;
      break;
    case InputKind::kSpeed: s.value[0] = 0.15 + 0.05 * std::sin(1.7 * t); break;
    case InputKind::kTemperature: s.value[0] = 40.0; break;
  }
  return s;
}

constexpr InputKind kRequired[] = {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed};

/// The offline replay's loss over samples 0..n-1 of every required input (the reference).
double offlineLoss_kg(int n, double* unaccounted_s) {
  ReplaySettings settings;
  settings.update_rate_hz = kRate_hz;
  settings.model = fastOptions();
  settings.threads = 1;
  ReplayWheel wheel;
  wheel.name = "w";
  DriveReplay replay(settings, {wheel});
  for (int k = 0; k < n; ++k)
    for (InputKind kind : kRequired) replay.addSample(0, rigSample(kind, k));
  replay.run();
  *unaccounted_s = replay.records(0).back().unaccounted_time_s;
  return replay.records(0).back().accumulated_loss_kg;
}

/// A wheel stepped on its inputs' stamps through an InputTimeline, as the node does under simulated time.
struct TimelineWheel {
  explicit TimelineWheel(const InputTimelineParams& params = InputTimelineParams())
      : timeline(params), model(TireParams(), fastOptions()), estimator(WheelEstimatorParams(), MaterialParams()) {}
  /// One arrival at wall time wall_s: the pipeline's handling of a full ring and a backward jump, then every step due.
  void receive(const InputSample& s, double wall_s) {
    InputTimeline::Push pushed = timeline.push(s, wall_s);
    if (pushed == InputTimeline::Push::kBackward) {
      release(wall_s, true);
      timeline.restart();
      pushed = timeline.push(s, wall_s);
    }
    while (pushed == InputTimeline::Push::kFull && releaseOne(wall_s, true)) pushed = timeline.push(s, wall_s);
    ASSERT_EQ(pushed, InputTimeline::Push::kTaken);
    release(wall_s, false);
  }
  bool releaseOne(double wall_s, bool flush) {
    double t = 0.0;
    if (!timeline.nextStep(wall_s, 1.0 / kRate_hz, flush, &inputs, &t)) return false;
    step_times.push_back(t);
    estimator.step(t, inputs, model);
    return true;
  }
  void release(double wall_s, bool flush) {
    while (releaseOne(wall_s, flush)) {
    }
  }
  InputTimeline timeline;
  WearModel model;
  WheelEstimator estimator;
  WheelInputs inputs;
  std::vector<double> step_times;
};

TEST(InputTimeline, LateAndBurstyInputsGiveTheOfflineReplaysLoss) {
  const int n = 300;  // 6 s
  double offline_unaccounted_s = 0.0;
  const double reference_kg = offlineLoss_kg(n, &offline_unaccounted_s);
  ASSERT_GT(reference_kg, 0.0);
  // Load on time; slip 13 samples late; speed 40 samples (0.8 s of stamps) late and in bursts of 25; 1 ms of wall
  // time per arrival, so no input is ever given up.
  TimelineWheel wheel;
  double wall_s = 0.0;
  std::vector<int> next(3, 0);
  for (int tick = 0; next[0] < n || next[1] < n || next[2] < n; ++tick) {
    const int due[3] = {tick, tick - 13, tick < 40 ? -1 : (tick - 40) / 25 * 25 + 24};
    for (int i = 0; i < 3; ++i)
      for (; next[i] < n && (next[i] <= due[i] || tick >= n + 60); ++next[i])
        wheel.receive(rigSample(kRequired[i], next[i]), wall_s += 1e-3);
  }
  EXPECT_NEAR(wheel.estimator.output().accumulated_loss_kg, reference_kg, kRelTol * reference_kg);
  EXPECT_NEAR(wheel.estimator.unaccountedTime_s(), offline_unaccounted_s, 1e-9);
  EXPECT_EQ(wheel.estimator.staleSteps(), 0u);
  EXPECT_EQ(wheel.timeline.stepsPastLaggingInput(), 0u);
  EXPECT_NEAR(wheel.step_times.back(), 105.95, 1e-9) << "the last grid point before the last sample, 105.98 s";
}

TEST(InputTimeline, AnInputFarBehindIsWaitedForWhileItsWallTimeWaitLasts) {
  // All of the speed arrives 3 s of stamps (more than max_lead_s) after the others but within the same wall
  // instant: nothing is released past it, and the loss is the offline replay's.
  const int n = 200;
  double offline_unaccounted_s = 0.0;
  const double reference_kg = offlineLoss_kg(n, &offline_unaccounted_s);
  TimelineWheel wheel;
  for (int k = 0; k < n; ++k) {
    wheel.receive(rigSample(InputKind::kLoad, k), 0.0);
    wheel.receive(rigSample(InputKind::kSlip, k), 0.0);
    if (k >= 150) wheel.receive(rigSample(InputKind::kSpeed, k - 150), 0.0);
  }
  for (int k = 50; k < n; ++k) wheel.receive(rigSample(InputKind::kSpeed, k), 0.4);
  EXPECT_NEAR(wheel.estimator.output().accumulated_loss_kg, reference_kg, kRelTol * reference_kg);
  EXPECT_EQ(wheel.timeline.stepsPastLaggingInput(), 0u);
}

TEST(InputTimeline, AnInputThatStopsIsGivenUpAfterItsLeadAndWaitAndItsTimeIsLost) {
  InputTimelineParams params;  // max_lead_s 1 s
  params.wait_s = 1.005;       // off the 10 ms arrival grid below, so that no comparison is a tie
  TimelineWheel wheel(params);
  double wall_s = 0.0, lagging_since_wall_s = -1.0;
  // 2 s of all inputs, then 8 s of load and slip only, 10 ms of wall time per sample period.
  for (int k = 0; k < 500; ++k) {
    wall_s += 0.01;
    wheel.receive(rigSample(InputKind::kLoad, k), wall_s);
    wheel.receive(rigSample(InputKind::kSlip, k), wall_s);
    if (k < 100) wheel.receive(rigSample(InputKind::kSpeed, k), wall_s);
    const double last_speed_s = 100.0 + kSamplePeriod_s * std::min(k, 99);
    const double newest_s = 100.0 + kSamplePeriod_s * k;
    if (newest_s - last_speed_s > params.max_lead_s && lagging_since_wall_s < 0.0) lagging_since_wall_s = wall_s;
    if (lagging_since_wall_s < 0.0 || wall_s - lagging_since_wall_s <= params.wait_s) {
      // Within the lead, or seen lagging for less than the wait: held at the speed's last sample.
      ASSERT_LE(wheel.step_times.back(), last_speed_s + 1e-9) << "k = " << k;
    } else {
      // Given up: released up to max_lead_s behind the newest sample.
      ASSERT_NEAR(wheel.step_times.back(), newest_s - params.max_lead_s, 1.0 / kRate_hz + 1e-9) << "k = " << k;
    }
  }
  EXPECT_GT(wheel.timeline.stepsPastLaggingInput(), 0u);
  EXPECT_GT(wheel.estimator.staleSteps(), 0u);
  // Lost, not held: every released second after the speed turned stale (0.5 s after its last sample) is unaccounted.
  const double stale_from_s = 100.0 + kSamplePeriod_s * 99 + WheelEstimatorParams().stale_timeout_s;
  EXPECT_NEAR(wheel.estimator.unaccountedTime_s(WheelStatus::kStaleInput), wheel.step_times.back() - stale_from_s,
              1.0 / kRate_hz + 1e-9);
}

TEST(InputTimeline, ANodeThatWasNotRunningSawNothingLag) {
  // All three inputs stop arriving for 5 s of wall time (the node descheduled), then the backlog comes topic by
  // topic: 3 s of load, then 3 s of slip, then 3 s of speed, each run at one instant. Nothing is given up.
  TimelineWheel wheel;
  for (int k = 0; k < 50; ++k)
    for (InputKind kind : kRequired) wheel.receive(rigSample(kind, k), 0.001 * k);
  for (InputKind kind : kRequired)
    for (int k = 50; k < 200; ++k) wheel.receive(rigSample(kind, k), 5.0);
  EXPECT_EQ(wheel.timeline.stepsPastLaggingInput(), 0u);
  EXPECT_EQ(wheel.estimator.staleSteps(), 0u);
  double offline_unaccounted_s = 0.0;
  const double reference_kg = offlineLoss_kg(200, &offline_unaccounted_s);
  EXPECT_NEAR(wheel.estimator.output().accumulated_loss_kg, reference_kg, kRelTol * reference_kg);
}

TEST(InputTimeline, AFullRingReleasesStepsInsteadOfDroppingSamples) {
  InputTimelineParams params;
  params.capacity = 16;
  TimelineWheel wheel(params);
  // The speed runs 60 samples (1.2 s) behind within one wall instant: the load's ring fills, steps are released
  // past the speed (counted), which turns stale there; nothing is dropped.
  for (int k = 0; k < 200; ++k) {
    wheel.receive(rigSample(InputKind::kLoad, k), 0.0);
    wheel.receive(rigSample(InputKind::kSlip, k), 0.0);
    if (k >= 60) wheel.receive(rigSample(InputKind::kSpeed, k - 60), 0.0);
  }
  EXPECT_GT(wheel.timeline.fullRings(), 0u);
  EXPECT_GT(wheel.timeline.stepsPastLaggingInput(), 0u);
  EXPECT_GT(wheel.estimator.unaccountedTime_s(WheelStatus::kStaleInput), 0.0);
  EXPECT_LE(wheel.timeline.buffered(InputKind::kLoad), params.capacity);
  EXPECT_EQ(wheel.inputs.sample(InputKind::kLoad).received + wheel.timeline.buffered(InputKind::kLoad), 200u);
}

TEST(InputTimeline, ABackwardStampRestartsTheGridAndTheEstimatorCountsTheJump) {
  TimelineWheel wheel;
  for (int k = 0; k < 100; ++k)
    for (InputKind kind : kRequired) wheel.receive(rigSample(kind, k), 0.001 * k);
  const double loss_kg = wheel.estimator.output().accumulated_loss_kg;
  ASSERT_GT(loss_kg, 0.0);
  // A looping bag: the stamps start again at sample 0.
  InputSample back = rigSample(InputKind::kLoad, 0);
  EXPECT_EQ(wheel.timeline.push(back, 1.0), InputTimeline::Push::kBackward);
  for (int k = 0; k < 100; ++k)
    for (InputKind kind : kRequired) wheel.receive(rigSample(kind, k), 1.0 + 0.001 * k);
  EXPECT_EQ(wheel.estimator.backwardJumps(), 1u);
  EXPECT_GT(wheel.estimator.output().accumulated_loss_kg, loss_kg) << "integration resumed after the jump";
  EXPECT_LT(wheel.estimator.output().accumulated_loss_kg, 2.0 * loss_kg + 1e-18);
}

TEST(InputTimeline, TheTreadTemperatureIsWaitedForOnceItHasArrived) {
  TimelineWheel wheel;
  InputSample first = rigSample(InputKind::kTemperature, 0);
  wheel.receive(first, 0.0);
  for (int k = 0; k < 50; ++k)
    for (InputKind kind : kRequired) wheel.receive(rigSample(kind, k), 0.0);
  EXPECT_TRUE(wheel.step_times.empty() || wheel.step_times.back() <= first.t_s + 1e-9)
      << "steps wait for the temperature's next sample";
  wheel.receive(rigSample(InputKind::kTemperature, 49), 0.0);
  EXPECT_NEAR(wheel.step_times.back(), 100.95, 1e-9) << "the last grid point before sample 49, 100.98 s";
}

TEST(InputTimeline, ParamsNameTheBrokenField) {
  InputTimelineParams p;
  std::string error;
  EXPECT_TRUE(p.validate(&error));
  p.max_lead_s = 0.0;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("max_lead_s"), std::string::npos) << error;
  p = InputTimelineParams();
  p.wait_s = std::nan("");
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("wait_s"), std::string::npos) << error;
  p = InputTimelineParams();
  p.capacity = 1;
  EXPECT_FALSE(p.validate(&error));
  EXPECT_NE(error.find("capacity"), std::string::npos) << error;
  EXPECT_THROW(InputTimeline{p}, std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
