// The concealed-effect generator's drive design (drive_fleet.h) against references of its own: the distance a
// segment integrates against the cycle's distance times its repetitions, the truth without an effect against the
// base model, rough_road's truth against its formula, the plan's shape, the errors of bad specs; and one small
// drive case end to end through the diagnosis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/harness.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

constexpr double kCruise_mps = 15.0;  ///< the test cycle's cruising speed
constexpr double kRamp_s = 20.0, kHold_s = 60.0, kStop_s = 10.0;

/// A short cycle: from rest to 15 m/s in 20 s, 60 s at 15 m/s, to rest in 20 s, 10 s standing (dense samples, so
/// that the PCHIP interpolant is the linear ramps). Its distance: 15 (20/2 + 60 + 20/2) = 1200 m.
std::shared_ptr<const SpeedProfile> testCycle() {
  std::vector<double> t, v;
  for (double s = 0.0; s <= 2 * kRamp_s + kHold_s + kStop_s + 1e-9; s += 1.0) {
    t.push_back(s);
    const double up = s / kRamp_s, down = (2 * kRamp_s + kHold_s - s) / kRamp_s;
    v.push_back(kCruise_mps * std::clamp(std::min(up, down), 0.0, 1.0));
  }
  return std::make_shared<const SpeedProfile>(t, v);
}
constexpr double kCycleDistance_m = kCruise_mps * (kRamp_s / 2 + kHold_s + kRamp_s / 2);

/// The passenger tire the fleet drives on.
TireParams passengerTire() {
  return loadTireParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/passenger_205_55_r16.yaml");
}

DriveFleet testFleet() {
  DriveFleet f;
  VehicleParams car;  // the struct's passenger car
  VehicleParams heavy = car;
  heavy.name = "heavy";
  heavy.mass_kg += 400.0;
  f.vehicles = {car, heavy};
  f.profile = testCycle();
  f.checkpoints = 4;
  f.segment_distance_m = 30e3;
  return f;
}

ConcealSpec driveSpec(const std::string& effect, double magnitude = std::numeric_limits<double>::quiet_NaN()) {
  ConcealSpec s;
  s.design = "drives";
  s.fleet = testFleet();
  s.effect = effect;
  s.magnitude = magnitude;
  s.wear_noise_rsd = 0.0;
  s.seed = 5;
  return s;
}

int column(const RunTable& t, const std::string& name) {
  return static_cast<int>(std::find(t.covariate_names.begin(), t.covariate_names.end(), name) -
                          t.covariate_names.begin());
}

}  // namespace

TEST(DriveDesign, SegmentsPerWheelAreCheckpointsLessOne) {
  RunTable table;
  const DriveFleet fleet = testFleet();
  const std::vector<DriveSegmentRuns> segments = simulateDriveFleet(fleet, 3, &table);
  std::map<std::pair<std::string, std::string>, int> per_wheel;
  for (const RunRecord& r : table.runs) ++per_wheel[{r.text_covariates[0], r.text_covariates[1]}];
  EXPECT_EQ(per_wheel.size(), fleet.vehicles.size() * kWheelCount);
  for (const auto& [wheel, count] : per_wheel) EXPECT_EQ(count, fleet.checkpoints - 1) << wheel.first;
  EXPECT_EQ(segments.size(), fleet.vehicles.size() * (fleet.checkpoints - 1));
}

TEST(DriveDesign, DistanceIsTheCycleIntegralTimesRepetitions) {
  RunTable table;
  const DriveFleet fleet = testFleet();
  const std::vector<DriveSegmentRuns> segments = simulateDriveFleet(fleet, 3, &table);
  const int speed_scale = column(table, "speed_scale");
  for (const DriveSegmentRuns& seg : segments) {
    // The cycle as driven: its speeds scaled (same times), so its distance is the scale times 1200 m; the driving
    // style changes the time, not the route's distance (driving_style.h).
    const double cycle_m = seg.runs.front().covariates[speed_scale] * kCycleDistance_m;
    EXPECT_EQ(seg.repetitions, std::lround(fleet.segment_distance_m / cycle_m));
    double sum_m = 0.0;
    for (const RunRecord& r : seg.runs) {
      double weights_m = 0.0;
      for (const WeightedOperatingPoint& p : r.drive_points) weights_m += p.distance_m;
      // No zero-load steps on a drive: the points carry the whole distance.
      EXPECT_NEAR(weights_m, r.drive_distance_m, 1e-9 * r.drive_distance_m);
      sum_m += r.drive_distance_m;
    }
    // The wheels' mean distance is the CoG's (curves: the outer wheels gain what the inner ones lose, to first
    // order in track / radius); 0.5%: the trapezoid rule at 10 Hz, the cells' second-order rest, the stops'
    // smoothing.
    EXPECT_NEAR(sum_m / kWheelCount, seg.repetitions * cycle_m, 5e-3 * seg.repetitions * cycle_m);
  }
}

TEST(DriveDesign, TruthWithoutEffectIsTheBaseModel) {
  const TireParams base = passengerTire();
  const ConcealSpec spec = driveSpec("none");
  const ConcealCase c = concealEffect(base, spec);
  const DiagnosisData data = buildDiagnosisData(c.noise_free);
  Prediction p;
  ASSERT_TRUE(ExtendedModel(base, spec.model, {}, data)
                  .predict({c.answer.parameters.at("w3_scale"), c.answer.parameters.at("mu_scale")}, &p));
  ASSERT_EQ(c.table.runs.size(), p.wear_kg_per_m.size());
  for (std::size_t i = 0; i < p.wear_kg_per_m.size(); ++i) {
    EXPECT_NEAR(c.noise_free.runs[i].measured_wear_rate_kg_per_m, p.wear_kg_per_m[i], 1e-12 * p.wear_kg_per_m[i]);
    // Without noise the measurement is the truth; drives measure no side force.
    EXPECT_NEAR(c.table.runs[i].measured_wear_rate_kg_per_m, p.wear_kg_per_m[i], 1e-12 * p.wear_kg_per_m[i]);
    EXPECT_TRUE(std::isnan(c.table.runs[i].measured_side_force_n));
  }
}

// The concealment applied to given recordings (a fleet's segments read from its bags): without an effect the base
// model at the file's levels, and contact_time_wear adds wear in proportion to w4 (W_r += w4 4ab / V).
TEST(DriveDesign, ConcealInRecordingsIsTheBaseModelPlusTheTerm) {
  const TireParams base = passengerTire();
  const ConcealSpec spec = driveSpec("none");
  const RunTable recordings = concealEffect(base, spec).table;
  const ConcealCase plain = concealInRecordings(base, recordings, "none", NAN, spec.model);
  Prediction p;
  ASSERT_TRUE(ExtendedModel(base, spec.model, {}, buildDiagnosisData(recordings)).predict({1.0, 1.0}, &p));
  const ConcealCase small = concealInRecordings(base, recordings, "contact_time_wear", 1e-6, spec.model);
  const ConcealCase large = concealInRecordings(base, recordings, "contact_time_wear", 2e-6, spec.model);
  ASSERT_EQ(recordings.runs.size(), plain.table.runs.size());
  for (std::size_t i = 0; i < p.wear_kg_per_m.size(); ++i) {
    const double none = plain.table.runs[i].measured_wear_rate_kg_per_m;
    EXPECT_NEAR(none, p.wear_kg_per_m[i], 1e-12 * p.wear_kg_per_m[i]);
    const double added = small.table.runs[i].measured_wear_rate_kg_per_m - none;
    EXPECT_GT(added, 0.0);
    EXPECT_NEAR(large.table.runs[i].measured_wear_rate_kg_per_m - none, 2.0 * added, 1e-9 * none);
  }
  EXPECT_EQ(1e-6, small.answer.primary_value);
  EXPECT_EQ(1.0, small.answer.parameters.at("w3_scale"));
  EXPECT_THROW(concealInRecordings(base, recordings, "no_such_term", NAN, spec.model), std::invalid_argument);
}

TEST(DriveDesign, RoughRoadScalesTheTruthByItsShare) {
  const TireParams base = passengerTire();
  const double beta = 0.6;
  const ConcealCase plain = concealEffect(base, driveSpec("none"));
  const ConcealCase rough = concealEffect(base, driveSpec(kRoughRoadEffect, beta));
  const int share = column(rough.table, "rough_road_share");
  double lo = 1.0, hi = 0.0;
  for (std::size_t i = 0; i < rough.table.runs.size(); ++i) {
    const double x = rough.table.runs[i].covariates[share];
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    EXPECT_NEAR(
        rough.noise_free.runs[i].measured_wear_rate_kg_per_m / plain.noise_free.runs[i].measured_wear_rate_kg_per_m,
        1.0 + beta * (x - 0.35), 1e-12);
  }
  EXPECT_GT(hi - lo, 0.1) << "the share must vary between segments for the effect to show";
  EXPECT_EQ(rough.answer.primary_value, beta);
  EXPECT_EQ(rough.answer.primary_neutral, 0.0);
}

TEST(DriveDesign, GaugeNoiseTelescopesOverAWheel) {
  // With a tread-depth gauge only, a wheel's measured losses sum to its true loss plus the first reading's error
  // minus the last one's: two readings, whatever the number of segments. 30 wheels-worth of checks: the sum's
  // spread must be sqrt(2) sigma, not sqrt(2 segments) sigma as independent per-segment errors would give.
  RunTable table;
  DriveFleet fleet = testFleet();
  fleet.checkpoints = 9;
  const std::vector<DriveSegmentRuns> segments = simulateDriveFleet(fleet, 3, &table);
  const double sigma_m = 1e-4, mass_per_depth = 40.0;  // 0.1 mm, a passenger tire's ~40 kg/m
  std::vector<double> truth(table.runs.size(), 1e-6);  // 1 mg/m
  double sum_sq = 0.0;
  int n = 0;
  for (std::uint64_t seed = 1; seed <= 15; ++seed) {
    const std::vector<double> m = measureDriveWear(segments, truth, 0.0, sigma_m, mass_per_depth, seed);
    std::map<std::pair<int, int>, double> error_kg;  // (vehicle, wheel) -> sum of (measured - true) loss
    std::size_t i = 0;
    for (const DriveSegmentRuns& seg : segments)
      for (int w = 0; w < kWheelCount; ++w, ++i)
        error_kg[{seg.vehicle, w}] += (m[i] - truth[i]) * seg.runs[w].drive_distance_m;
    for (const auto& [key, e] : error_kg) {
      sum_sq += e * e;
      ++n;
    }
  }
  const double rms_depth_m = std::sqrt(sum_sq / n) / mass_per_depth;
  // 120 sums: the RMS estimates sqrt(2) sigma = 0.141 mm within about 13% (chi-square, 2 sigma); independent
  // errors would give sqrt(16) sigma = 0.4 mm.
  EXPECT_NEAR(rms_depth_m, std::sqrt(2.0) * sigma_m, 0.2 * std::sqrt(2.0) * sigma_m);
}

TEST(DriveDesign, BadSpecsNameTheField) {
  auto error = [](const DriveFleet& f) {
    std::string e;
    EXPECT_FALSE(f.validate(&e));
    return e;
  };
  DriveFleet f = testFleet();
  f.checkpoints = 1;
  EXPECT_NE(error(f).find("checkpoints = 1"), std::string::npos) << error(f);
  f = testFleet();
  f.profile.reset();
  EXPECT_NE(error(f).find("profile"), std::string::npos);
  f = testFleet();
  f.vehicles.clear();
  EXPECT_NE(error(f).find("vehicles"), std::string::npos);
  f = testFleet();
  f.vehicles[1].mass_kg = -1.0;
  EXPECT_NE(error(f).find("vehicles[1]: mass_kg"), std::string::npos) << error(f);
  f = testFleet();
  f.segment_distance_m = 0.0;
  EXPECT_NE(error(f).find("segment_distance_m"), std::string::npos);
  f = testFleet();
  f.depth_gauge_sigma_m = -1e-4;
  EXPECT_NE(error(f).find("depth_gauge_sigma_m"), std::string::npos);

  ConcealSpec s = driveSpec(kRoughRoadEffect);
  s.design = "table2";  // rough_road is a drive effect only
  std::string e;
  EXPECT_FALSE(s.validate(&e));
  EXPECT_NE(e.find("effect = 'rough_road'"), std::string::npos) << e;
  s = driveSpec("none");
  s.fleet.checkpoints = 0;
  EXPECT_FALSE(s.validate(&e));
  EXPECT_NE(e.find("checkpoints = 0"), std::string::npos) << e;
  EXPECT_THROW(concealEffect(passengerTire(), s), std::invalid_argument);
}

TEST(DriveDesign, SmallDriveCaseEndToEnd) {
  // Two vehicles, four checkpoints, the short cycle: 24 segments. thermal_wear at sigma_T = 20 degC (a strong
  // effect: the seasons' 0-25 degC move w3 by a factor of up to 2) at 2% wear noise, generated and diagnosed at
  // `fast` (the machinery, not the success rates of docs/diagnosis.md); the scoring names it right. About 15 s.
  const TireParams base = passengerTire();
  ConcealSpec spec = driveSpec("thermal_wear", 20.0);
  spec.wear_noise_rsd = 0.02;
  const ConcealCase c = concealEffect(base, spec);
  DiagnosisOptions opt;
  opt.auto_preset = false;
  opt.max_terms = 1;
  // Competitors that act per cell through the brush model (thermal_friction too would double the time: it builds a
  // brush model per cell).
  opt.candidates = {Term::kThermalWear, Term::kPressureFriction, Term::kLoadFluctuation};
  opt.permutations = 999;
  opt.detection_power = 0.0;
  const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
  EXPECT_EQ(r.explanation, "thermal_wear");
  const HarnessOutcome o = scoreCase(HarnessCase{spec, "test"}, c.answer, r);
  EXPECT_TRUE(o.right);
  EXPECT_TRUE(o.improved);
}
