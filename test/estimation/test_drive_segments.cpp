// DriveSegmenter (drive_segments.h) against the offline replay (DriveReplay, which evaluates the model at every
// step): the same integrated time and distance per segment, and, with cells fine enough to hold one step each, the
// replay's wear as sum W_r(point) x distance weight to rounding (the trapezoid rule split onto its ends, with the
// low-speed convention). Input gaps, stale inputs, zero load and low speed included; a gap is skipped, not stepped.
// PointCells keep the weights and first moments of the points they merge. Bad arguments name the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "tread_wear/estimation/drive_segments.h"
#include "tread_wear/model/point_cells.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

constexpr double kStart_s = 100.0;

ReplaySettings settings() {
  ReplaySettings s;
  s.update_rate_hz = 20.0;
  s.model.preset = Preset::kFast;
  s.threads = 1;
  return s;
}

/// Cells so narrow that no two distinct steps share one.
PointCellParams stepCells() {
  PointCellParams p;
  for (CellAxis* a : {&p.load, &p.slip_angle, &p.slip_ratio, &p.speed, &p.path_curvature}) *a = {1e-6, 1e-6};
  p.temperature_bin_c = 1e-6;
  return p;
}

/// A 10 Hz rig-like drive of 300 s with a pause of 40 s (inputs stop), a wheel off the ground for 5 s (zero load),
/// a crawl below the low-speed threshold and random slips; temperatures on the second half only.
std::vector<InputSample> drive() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<InputSample> out;
  for (int k = 0; k < 3000; ++k) {
    const double t = kStart_s + 0.1 * k;
    if (t > 200.0 && t < 240.0) continue;  // pause: every input stale, then restarts
    auto add = [&](InputKind kind, double a, double b = 0.0, double c = 0.0) {
      InputSample s;
      s.t_s = t;
      s.kind = kind;
      s.value[0] = a;
      s.value[1] = b;
      s.value[2] = c;
      out.push_back(s);
    };
    add(InputKind::kLoad, (t > 150.0 && t < 155.0) ? 0.0 : 75.0 + 15.0 * u(rng));
    add(InputKind::kSlip, (-3.0 + 2.0 * u(rng)) * units::kDegree, 0.02 * u(rng), 1.0 / 0.06);
    add(InputKind::kSpeed, (t > 300.0 && t < 310.0) ? 0.05 : 1.5 + 0.5 * u(rng));
    if (t > 250.0) add(InputKind::kTemperature, 40.0 + 5.0 * u(rng));
  }
  return out;
}

TEST(DriveSegments, EqualTheReplayPerSegment) {
  // The last checkpoint before the last sample (399.9 s): the replay does not step past its last sample.
  const std::vector<double> checkpoints = {kStart_s, 180.0, 260.0, 330.0, 399.0};
  const std::vector<InputSample> samples = drive();

  ReplayWheel wheel;
  wheel.name = "w";
  DriveReplay replay(settings(), {wheel});
  DriveSegmenter segmenter(settings(), stepCells(), checkpoints, kStart_s);
  for (const InputSample& s : samples) {
    replay.addSample(0, s);
    segmenter.addSample(s);
  }
  replay.run();
  const std::vector<DriveSegment> segments = segmenter.finish();
  ASSERT_EQ(segments.size(), checkpoints.size() - 1);

  const std::vector<StepRecord>& records = replay.records(0);
  const WearModel model(wheel.tire, settings().model);
  for (std::size_t j = 0; j < segments.size(); ++j) {
    SCOPED_TRACE("segment " + std::to_string(j + 1));
    // The replay's integrals over the intervals ending in (checkpoint j, checkpoint j+1].
    double loss = 0.0, distance = 0.0, integrated = 0.0;
    for (std::size_t k = 1; k < records.size(); ++k) {
      const double t = replay.stepTime(k);
      if (!(t > checkpoints[j] + 1e-9) || t > checkpoints[j + 1] + 1e-9 || !records[k].integrated) continue;
      loss += records[k].accumulated_loss_kg - records[k - 1].accumulated_loss_kg;
      distance += records[k].distance_m - records[k - 1].distance_m;
      integrated += 1.0 / settings().update_rate_hz;
    }
    const DriveSegment& s = segments[j];
    EXPECT_NEAR(s.distance_m, distance, 1e-9 * distance);
    EXPECT_NEAR(s.integrated_s, integrated, 1e-9);
    EXPECT_NEAR(s.unaccounted_s, (checkpoints[j + 1] - checkpoints[j]) - integrated, 1e-9);
    // Sum W_r(point) x distance weight, each point evaluated as the node would (its speed is raised below
    // min_speed_mps, W_r held: lowSpeedPoint), is the replay's loss.
    double predicted = 0.0;
    for (const WeightedOperatingPoint& p : s.points) {
      WearResult r;
      ASSERT_NE(model.evaluate(p.op, &r), EvalStatus::kInvalidInput);
      predicted += r.wear_rate_kg_per_m * p.distance_m;
    }
    EXPECT_NEAR(predicted, loss, 1e-9 * loss);
  }
  // The pause (200-240 s) is lost in segment 2; segment 1 (with the wheel off the ground, which is integrated with
  // no wear) is integrated from its start.
  EXPECT_GT(segments[1].unaccounted_s, 39.0);  // 200.4 s (inputs stale) to 240 s
  EXPECT_LT(segments[0].unaccounted_s, 1e-9);
}

TEST(DriveSegments, DefaultCellsKeepTheIntegralsAndFewPoints) {
  const std::vector<double> checkpoints = {kStart_s, 400.0};
  DriveSegmenter fine(settings(), stepCells(), checkpoints, kStart_s), binned(settings(), PointCellParams(), checkpoints,
                                                                                kStart_s);
  for (const InputSample& s : drive()) {
    fine.addSample(s);
    binned.addSample(s);
  }
  const DriveSegment a = fine.finish().front(), b = binned.finish().front();
  double time_a = 0.0, time_b = 0.0, dist_a = 0.0, dist_b = 0.0, alpha_a = 0.0, alpha_b = 0.0;
  for (const WeightedOperatingPoint& p : a.points) {
    time_a += p.time_s;
    dist_a += p.distance_m;
    alpha_a += p.distance_m * p.op.slip_angle_rad;
  }
  for (const WeightedOperatingPoint& p : b.points) {
    time_b += p.time_s;
    dist_b += p.distance_m;
    alpha_b += p.distance_m * p.op.slip_angle_rad;
  }
  EXPECT_NEAR(time_b, time_a, 1e-9 * time_a);
  EXPECT_NEAR(dist_b, dist_a, 1e-9 * dist_a);
  EXPECT_NEAR(alpha_b, alpha_a, 1e-9 * std::abs(alpha_a));  // distance-weighted centroids: first moment kept
  EXPECT_LT(b.points.size(), a.points.size());
}

TEST(DriveSegments, GapsAreSkippedNotStepped) {
  // Two 10 s drives 30 days apart (2.6e9 grid steps between them at 1 kHz, if they were stepped): the result is
  // twice that of one drive alone.
  const double month_s = 30 * 86400.0;
  ReplaySettings fast_grid = settings();
  fast_grid.update_rate_hz = 1000.0;
  auto samples = [](double offset) {
    std::vector<InputSample> out;
    for (int k = 0; k < 100; ++k)
      for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed}) {
        InputSample s;
        s.t_s = kStart_s + offset + 0.1 * k;
        s.kind = kind;
        s.value[0] = kind == InputKind::kLoad ? 75.0 : kind == InputKind::kSpeed ? 2.0 : -0.05;
        out.push_back(s);
      }
    return out;
  };
  DriveSegmenter one(fast_grid, PointCellParams(), {kStart_s - 1.0, kStart_s + 30.0}, kStart_s);
  DriveSegmenter two(fast_grid, PointCellParams(), {kStart_s - 1.0, kStart_s + month_s + 30.0}, kStart_s);
  for (double offset : {0.0, month_s})
    for (const InputSample& s : samples(offset)) {
      if (offset == 0.0) one.addSample(s);
      two.addSample(s);
    }
  const DriveSegment a = one.finish().front(), b = two.finish().front();
  ASSERT_GT(a.integrated_s, 9.9);
  EXPECT_NEAR(b.integrated_s, 2 * a.integrated_s, 1e-6);
  EXPECT_NEAR(b.distance_m, 2 * a.distance_m, 1e-6);
  ASSERT_EQ(b.points.size(), 1u);  // one condition
}

TEST(DriveSegments, BadArgumentsNameTheProblem) {
  auto error = [](auto make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error([] { DriveSegmenter(settings(), {}, {1.0}, 0.0); }).find("1 checkpoints, at least 2"),
            std::string::npos);
  EXPECT_NE(error([] { DriveSegmenter(settings(), {}, {1.0, 1.0}, 0.0); }).find("checkpoint 2 at t = 1"),
            std::string::npos);
  EXPECT_NE(error([] { DriveSegmenter(settings(), {}, {1.0, NAN}, 0.0); }).find("checkpoint 2"), std::string::npos);
  ReplaySettings bad = settings();
  bad.update_rate_hz = -1.0;
  EXPECT_NE(error([&] { DriveSegmenter(bad, {}, {0.0, 1.0}, 0.0); }).find("update_rate_hz"), std::string::npos);
  PointCellParams cells;
  cells.slip_angle.width = 0.0;
  EXPECT_NE(error([&] { DriveSegmenter(settings(), cells, {0.0, 1.0}, 0.0); }).find("slip_angle.width"),
            std::string::npos);
  DriveSegmenter ordered(settings(), {}, {0.0, 10.0}, 0.0);
  InputSample s;
  s.t_s = 5.0;
  ordered.addSample(s);
  s.t_s = 4.0;
  EXPECT_NE(error([&] { ordered.addSample(s); }).find("comes before the previous one"), std::string::npos);
}

}  // namespace
}  // namespace tread_wear
