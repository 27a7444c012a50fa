// Issue 36: the diagnosis of drives at its default settings. The solver-error check on a sample of the drive cells
// against the same check on every cell (its definition, numerics_check.h), and the cell evaluations on one and on
// two threads against each other (they must agree bit for bit, parallel_for.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/numerics_check.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/proving/conceal.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

/// A short cycle: from rest to 15 m/s in 20 s, 60 s at 15 m/s, to rest in 20 s, 10 s standing.
std::shared_ptr<const SpeedProfile> testCycle() {
  std::vector<double> t, v;
  for (double s = 0.0; s <= 110.0 + 1e-9; s += 1.0) {
    t.push_back(s);
    v.push_back(15.0 * std::clamp(std::min(s / 20.0, (100.0 - s) / 20.0), 0.0, 1.0));
  }
  return std::make_shared<const SpeedProfile>(t, v);
}

/// The road tire with its sliding wear alone: the noise levels below are set against fast's solver error in the
/// sliding term (several % in W_r); the adhesion-zone term is the same at every preset and would dilute it.
TireParams passengerTire() {
  TireParams p = loadTireParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/passenger_205_55_r16.yaml");
  p.wear.adhesion_kg_per_j = 0.0;
  return p;
}

/// Two vehicles, four checkpoints: 24 drive segments sharing a few hundred coarse cells.
ConcealCase driveCase(const std::string& effect, double magnitude, double wear_noise_rsd, std::uint64_t seed) {
  ConcealSpec s;
  s.design = "drives";
  VehicleParams car, heavy;
  heavy.name = "heavy";
  heavy.mass_kg += 400.0;
  s.fleet.vehicles = {car, heavy};
  s.fleet.profile = testCycle();
  s.fleet.checkpoints = 4;
  s.fleet.segment_distance_m = 30e3;
  s.effect = effect;
  s.magnitude = magnitude;
  s.wear_noise_rsd = wear_noise_rsd;
  s.model.preset = Preset::kFast;  // generated at the diagnosis's first preset: the machinery, not the rates
  s.seed = seed;
  return concealEffect(passengerTire(), s);
}

}  // namespace

TEST(DriveNumerics, SampledCheckBracketsTheCheckOnEveryCell) {
  // The reference is the check's own definition, every coarse cell predicted at both presets. A wear noise of
  // 0.5% makes fast's solver error (several % in W_r on these cells) fail the check, one of 5% pass it. Three
  // sample seeds each: the interval is a 95% one (by the triangle inequality, conservative); allow one miss.
  const TireParams base = passengerTire();
  const DiagnosisData data = buildDiagnosisData(driveCase("none", 0.0, 0.0, 3).table);
  ExtendedModelOptions model;
  model.jobs = 2;
  NoiseModel noise[kNumOutputs];
  for (int limit_case = 0; limit_case < 2; ++limit_case) {
    noise[0].relative = 0.02;
    noise[1].relative = limit_case == 0 ? 0.005 : 0.05;
    const std::vector<double> values = {1.1, 0.95};  // off the base, so that the coarse cells are re-simulated
    NumericsSampling every;
    every.first_sample_cells = 0;
    const NumericsCheck full = checkNumerics(base, data, model, {}, values, noise, 1.0, every);
    ASSERT_FALSE(full.sampled);
    ASSERT_GT(full.cells, 100);
    EXPECT_EQ(full.cells_compared, full.cells);
    int covered = 0, same_decision = 0;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      NumericsSampling sample;
      sample.first_sample_cells = full.cells / 8;
      sample.seed = seed;
      const NumericsCheck s = checkNumerics(base, data, model, {}, values, noise, 1.0, sample);
      if (s.noncentrality_low <= full.noncentrality && full.noncentrality <= s.noncentrality_high) ++covered;
      if (s.passed == full.passed) ++same_decision;
      EXPECT_LE(s.cells_compared, full.cells);
    }
    EXPECT_GE(covered, 2) << "full lambda " << full.noncentrality;
    EXPECT_EQ(same_decision, 3) << "full lambda " << full.noncentrality;
  }
}

TEST(DriveNumerics, SampleOfEveryCellIsTheFullCheck) {
  // With the first sample as large as the cells, every inclusion probability is 1: the estimate is the sum over
  // all cells, i.e. the full check to round-off, with an interval of zero width.
  const TireParams base = passengerTire();
  const DiagnosisData data = buildDiagnosisData(driveCase("none", 0.0, 0.0, 4).table);
  NoiseModel noise[kNumOutputs];
  noise[0].relative = 0.02;
  noise[1].relative = 0.01;
  const std::vector<double> values = {1.0, 1.05};
  NumericsSampling every;
  every.first_sample_cells = 0;
  const NumericsCheck full = checkNumerics(base, data, ExtendedModelOptions(), {}, values, noise, 1.0, every);
  NumericsSampling all;
  all.first_sample_cells = (full.cells + 3) / 4;  // sampling on; the next, fourfold, sample holds every cell
  all.confidence = 0.999999;
  // The limit at the full check's lambda: the first sample's interval straddles it, so the sample grows to all.
  const NumericsCheck s = checkNumerics(base, data, ExtendedModelOptions(), {}, values, noise, full.noncentrality, all);
  EXPECT_FALSE(s.sampled);
  EXPECT_EQ(s.cells_compared, full.cells);
  EXPECT_NEAR(s.noncentrality, full.noncentrality, 1e-9 * (1.0 + full.noncentrality));
  EXPECT_NEAR(s.outputs[1].rms_relative, full.outputs[1].rms_relative, 1e-9);
}

TEST(DriveNumerics, JobsOneAndTwoGiveIdenticalResults) {
  // A small drive case (thermal_wear at sigma_T = 20 degC, 2% noise) diagnosed with one and with two threads,
  // each on its own copy of the data (no cache shared between the two runs): every verdict, estimate, held-out
  // error and solver-error figure must be the same bit for bit. At `fast` given (its check is still run and
  // reported; `auto` would escalate on these generated-at-fast recordings and triple the time).
  const TireParams base = passengerTire();
  const ConcealCase c = driveCase("thermal_wear", 20.0, 0.02, 5);
  DiagnosisResult results[2];
  for (int jobs = 1; jobs <= 2; ++jobs) {
    DiagnosisOptions opt;
    opt.model.jobs = jobs;
    opt.auto_preset = false;
    opt.max_terms = 1;
    opt.candidates = {Term::kThermalWear};           // the base fit's mu_scale re-simulates the cells on both threads
    opt.numerics_sampling.first_sample_cells = 100;  // the sampled check too
    opt.permutations = 999;
    opt.detection_power = 0.0;
    results[jobs - 1] = diagnose(base, buildDiagnosisData(c.table), opt);
  }
  const DiagnosisResult &a = results[0], &b = results[1];
  EXPECT_EQ(a.explanation, "thermal_wear");
  EXPECT_EQ(a.explanation, b.explanation);
  EXPECT_EQ(a.preset, b.preset);
  ASSERT_EQ(a.final_model.summary.parameters.size(), b.final_model.summary.parameters.size());
  for (std::size_t k = 0; k < a.final_model.summary.parameters.size(); ++k)
    EXPECT_EQ(a.final_model.summary.parameters[k].value, b.final_model.summary.parameters[k].value);
  for (int o = 0; o < kNumOutputs; ++o) {
    if (std::isfinite(a.final_model.cv_rmser[o])) EXPECT_EQ(a.final_model.cv_rmser[o], b.final_model.cv_rmser[o]);
    if (std::isfinite(a.base.cv_rmser[o])) EXPECT_EQ(a.base.cv_rmser[o], b.base.cv_rmser[o]);
  }
  ASSERT_EQ(a.numerics.size(), b.numerics.size());
  for (std::size_t k = 0; k < a.numerics.size(); ++k) {
    EXPECT_EQ(a.numerics[k].noncentrality, b.numerics[k].noncentrality);
    EXPECT_EQ(a.numerics[k].noncentrality_high, b.numerics[k].noncentrality_high);
  }
  ASSERT_EQ(a.tried.size(), b.tried.size());
  for (std::size_t k = 0; k < a.tried.size(); ++k) EXPECT_EQ(a.tried[k].aicc, b.tried[k].aicc);
  EXPECT_FALSE(a.timings.empty());
}

TEST(DriveNumerics, InterpolatedFrictionMatchesTheDirectEvaluation) {
  // The coarse cells interpolated between the friction nodes (interpolate_mu_scale) against every cell evaluated
  // at the friction factor itself, off the nodes (mu_scale 0.937, and thermal_friction at k_T = 0.004 / K, which
  // puts each cell at its own factor): the segments' predicted wear within 1e-4 (measured 5.8e-5), and within 5e-4
  // with thermal_friction, whose direct evaluation rounds each cell's temperature to 0.1 degC (a friction factor
  // off by up to k_T x 0.05 K = 2e-4; measured 1.7e-4). The coarse cells' own error against the fine ones is 0.5%
  // (docs/diagnosis.md), so the interpolation adds nothing a fit could see.
  constexpr double kTolerance = 1e-4, kThermalTolerance = 5e-4;
  const TireParams base = passengerTire();
  const DiagnosisData data = buildDiagnosisData(driveCase("none", 0.0, 0.0, 6).table);
  for (const std::vector<Term>& terms : {std::vector<Term>{}, std::vector<Term>{Term::kThermalFriction}}) {
    ExtendedModelOptions direct_options;
    direct_options.coarse_cells_only = true;
    direct_options.interpolate_mu_scale = false;
    ExtendedModelOptions interpolated_options = direct_options;
    interpolated_options.interpolate_mu_scale = true;
    const ExtendedModel direct(base, direct_options, terms, data),
        interpolated(base, interpolated_options, terms, data);
    std::vector<double> values = {1.0, 0.937};
    if (!terms.empty()) values.push_back(0.004);
    Prediction a, b;
    ASSERT_TRUE(direct.predict(values, &a));
    ASSERT_TRUE(interpolated.predict(values, &b));
    double worst = 0.0;
    for (std::size_t i = 0; i < data.runs.size(); ++i)
      worst = std::max(worst, std::abs(b.wear_kg_per_m[i] / a.wear_kg_per_m[i] - 1.0));
    EXPECT_LT(worst, terms.empty() ? kTolerance : kThermalTolerance) << termsLabel(terms);
    std::printf("%s: largest relative wear difference of a segment %.3g\n", termsLabel(terms).c_str(), worst);
  }
}

TEST(DriveNumerics, ComplianceRootSatisfiesItsEquationOnThePassengerTire) {
  // lateral_compliance's effective slip angle is the root of a = alpha + c Fy(a). The reference is the equation
  // itself: the brush model evaluated on its own at a = alpha + c Fy (Fy the prediction) must give that Fy back,
  // with a between 0 and alpha (the side force opposes the slip). The passenger tire's cornering stiffness makes
  // c |dFy/dalpha| 7 at 1e-4 rad/N and 200 at the term's bound 3e-3; the former solver's fixed-point first step
  // ended on the clamp at 1.5 rad there (from 4e-4 rad/N on).
  const TireParams base = passengerTire();
  RunTable table;
  for (double alpha : {0.005, 0.02, 0.05, 0.1}) {
    RunRecord r;
    r.op.speed_mps = 20.0;
    r.op.load_n = 4000.0;
    r.op.slip_angle_rad = alpha;
    r.measured_wear_rate_kg_per_m = 1e-8;
    r.condition_id = std::to_string(alpha);
    table.runs.push_back(r);
  }
  const DiagnosisData data = buildDiagnosisData(table);
  const ExtendedModel model(base, ExtendedModelOptions(), {Term::kLateralCompliance}, data);
  TireParams brush_params = base;
  brush_params.wear.temperature_enabled = false;
  const BrushWearModel brush(brush_params, presetOptions(Preset::kFast));
  for (double c : {1e-4, 4e-4, 3e-3}) {
    Prediction p;
    ASSERT_TRUE(model.predict({1.0, 1.0, c}, &p));
    for (std::size_t i = 0; i < data.runs.size(); ++i) {
      const double alpha = data.runs[i].op.slip_angle_rad;
      OperatingPoint op = data.runs[i].op;
      op.slip_angle_rad = alpha + c * p.side_force_n[i];
      EXPECT_GT(op.slip_angle_rad, 0.0) << "c " << c << ", alpha " << alpha;
      EXPECT_LT(op.slip_angle_rad, alpha) << "c " << c << ", alpha " << alpha;
      WearResult r;
      brush.evaluate(op, &r);
      // The root to 1e-8 rad (kComplianceTolerance_rad): Fy within the stiffness times that, about 1e-3 N.
      EXPECT_NEAR(r.fy_n, p.side_force_n[i], 1e-2) << "c " << c << ", alpha " << alpha;
    }
  }
}
