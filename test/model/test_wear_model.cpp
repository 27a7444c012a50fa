// WearModel facade: low-speed conventions (standstill, tiny speed, the threshold, locked wheel), the
// time-budget preset choice with injected timings, and invalid inputs and options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

OperatingPoint rigPoint(double speed) {
  OperatingPoint op;  // Table 3 benchmark condition on the rig
  op.speed_mps = speed;
  op.slip_angle_rad = -10.0 * units::kDegree;
  op.load_n = 75.0;
  op.path_curvature_per_m = 1.0 / 0.060;
  return op;
}

WearModelOptions fastOptions() {
  WearModelOptions o;
  o.preset = Preset::kFast;
  return o;
}

TEST(WearModelLowSpeed, StandstillGivesZeroWearPerTimeAndFiniteOutputs) {
  const WearModel model(TireParams(), fastOptions());
  WearResult r;
  EXPECT_EQ(model.evaluate(rigPoint(0.0), &r), EvalStatus::kLowSpeed);
  EXPECT_EQ(r.wear_rate_kg_per_s, 0.0);  // no rolling, no sliding: exactly zero
  EXPECT_TRUE(std::isfinite(r.wear_rate_kg_per_m));
  EXPECT_GT(r.wear_rate_kg_per_m, 0.0);
  EXPECT_TRUE(std::isfinite(r.fy_n) && std::isfinite(r.mz_nm) && std::isfinite(r.fx_n));
}

TEST(WearModelLowSpeed, BelowThresholdHoldsWearPerDistanceAndScalesWearPerTime) {
  const WearModel model(TireParams(), fastOptions());
  const double v_min = model.options().min_speed_mps;
  WearResult at_threshold, tiny, half;
  EXPECT_EQ(model.evaluate(rigPoint(v_min), &at_threshold), EvalStatus::kOk);
  EXPECT_EQ(model.evaluate(rigPoint(1e-9), &tiny), EvalStatus::kLowSpeed);
  EXPECT_EQ(model.evaluate(rigPoint(0.5 * v_min), &half), EvalStatus::kLowSpeed);
  // The convention: the threshold point's W_r and forces, wear per time = W_r V (continuous at v_min).
  EXPECT_DOUBLE_EQ(tiny.wear_rate_kg_per_m, at_threshold.wear_rate_kg_per_m);
  EXPECT_DOUBLE_EQ(tiny.fy_n, at_threshold.fy_n);
  EXPECT_DOUBLE_EQ(half.wear_rate_kg_per_s, 0.5 * at_threshold.wear_rate_kg_per_s);
  EXPECT_DOUBLE_EQ(tiny.wear_rate_kg_per_s, at_threshold.wear_rate_kg_per_m * 1e-9);
}

TEST(WearModelLowSpeed, LockedWheelRollingSpeedIsFloored) {
  const WearModel model(TireParams(), fastOptions());
  OperatingPoint op;
  op.speed_mps = 1.0;
  op.load_n = 100.0;
  op.slip_ratio = -1.0 + 1e-12;  // V_r = 1e-12 m/s: element transit time ~1e10 s without the floor
  WearResult r;
  EXPECT_EQ(model.evaluate(op, &r), EvalStatus::kLowSpeed);
  // Full sliding at V - V_r ~ V: a braking force (Fx < 0, ISO) bounded by the peak friction.
  EXPECT_TRUE(std::isfinite(r.fx_n));
  EXPECT_LT(r.fx_n, 0.0);
  const FrictionParams& f = model.params().friction;
  const double sat_max = std::pow(f.p_0_pa / f.p_ref_pa, -f.q);  // largest sat(p)
  EXPECT_LT(-r.fx_n, sat_max * f.mu_m * op.load_n);
  EXPECT_LT(r.stick_fraction, 0.05);  // nearly everything slides faster than v_m
  OperatingPoint rolling = op;
  rolling.slip_ratio = -0.5;  // V_r well above the floor: untouched
  EXPECT_EQ(model.evaluate(rolling, &r), EvalStatus::kOk);
}

TEST(WearModelBudget, PicksFinestPresetThatFitsFromInjectedTimings) {
  WearModelOptions o;
  o.preset = Preset::kStandard;
  o.time_budget_s = 50e-6;
  o.budget_probe_interval = 3;
  o.timing_smoothing = 1.0;  // the last time counts alone, so injected timings decide exactly
  const WearModel model(TireParams(), o);
  EXPECT_EQ(model.choosePreset(), Preset::kStandard);  // unmeasured: assumed to fit
  model.recordTiming(Preset::kStandard, 80e-6);
  model.recordTiming(Preset::kFast, 10e-6);
  EXPECT_EQ(model.choosePreset(), Preset::kFast);
  model.recordTiming(Preset::kStandard, 40e-6);
  EXPECT_EQ(model.choosePreset(), Preset::kStandard);
  model.recordTiming(Preset::kReference, 1e-9);  // finer than wanted: never chosen
  EXPECT_EQ(model.choosePreset(), Preset::kStandard);
}

TEST(WearModelBudget, ReportsDegradingAndProbesFinerPresetPeriodically) {
  WearModelOptions o;
  o.preset = Preset::kStandard;
  o.time_budget_s = 1e-12;  // nothing fits: every measured preset is over budget
  o.budget_probe_interval = 3;
  const WearModel model(TireParams(), o);
  WearResult r;
  model.evaluate(rigPoint(2.0), &r);  // standard, unmeasured: tried once and measured
  EXPECT_EQ(model.activePreset(), Preset::kStandard);
  EXPECT_FALSE(model.degraded());
  EXPECT_GT(model.timing(Preset::kStandard), 0.0);
  std::vector<Preset> used;
  for (int k = 0; k < 8; ++k) {
    model.evaluate(rigPoint(2.0), &r);
    used.push_back(model.activePreset());
  }
  // Fast for probe_interval evaluations, then one probe of standard, then fast again.
  const std::vector<Preset> expected{Preset::kFast, Preset::kFast, Preset::kFast, Preset::kStandard,
                                     Preset::kFast, Preset::kFast, Preset::kFast, Preset::kStandard};
  EXPECT_EQ(used, expected);
  EXPECT_EQ(model.degradedCount(), 6);
  EXPECT_TRUE(std::isfinite(r.fy_n));
}

TEST(WearModelBudget, FieldsPinThePresetOfTheirGrid) {
  WearModelOptions o;
  o.time_budget_s = 1e-12;  // would degrade to fast
  const WearModel model(TireParams(), o);
  model.recordTiming(Preset::kStandard, 1.0);
  PatchFields fields;
  const BrushWearModel& standard = model.solver(Preset::kStandard);
  fields.resize(standard.nodesX(), standard.strips());
  WearResult r;
  model.evaluate(rigPoint(2.0), &r, &fields);
  EXPECT_EQ(model.activePreset(), Preset::kStandard);  // the grid of the fields, not the budget's choice
  EXPECT_GT(fields.pressure_pa[fields.index(standard.nodesX() / 2, standard.strips() / 2)], 0.0);
  PatchFields odd;
  odd.resize(3, 3);  // no preset's grid: left untouched
  model.evaluate(rigPoint(2.0), &r, &odd);
  EXPECT_EQ(odd.pressure_pa[4], 0.0);
}

TEST(WearModelBudget, NoBudgetUsesWantedPresetAndNeverDegrades) {
  const WearModel model(TireParams(), fastOptions());
  WearResult r;
  for (int k = 0; k < 3; ++k) model.evaluate(rigPoint(2.0), &r);
  EXPECT_EQ(model.activePreset(), Preset::kFast);
  EXPECT_EQ(model.degradedCount(), 0);
  EXPECT_TRUE(std::isnan(model.timing(Preset::kFast)));  // not timed without a budget
}

// Robustness over the whole input domain (fixed seed): speeds 1e-3..100 m/s, |alpha| up to 89 deg,
// kappa from -0.999 to 2, loads 0.01..3x nominal, |curvature| up to 20 1/m. Every result is finite, the
// root iteration count stays inside its bound, and the friction bound holds: every stress (stick, creep
// or slide) is at most sat(p) mu_m p, so |(Fx, Fy)| <= max sat * mu_m * Fz.
TEST(WearModelInput, RandomPointsGiveFiniteFrictionBoundedResults) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const TireParams params;
  const FrictionParams& f = params.friction;
  const double sat_max = std::pow(f.p_0_pa / f.p_ref_pa, -f.q);
  for (Preset preset : {Preset::kFast, Preset::kStandard, Preset::kFine}) {
    WearModelOptions o;
    o.preset = preset;
    const WearModel model(params, o);
    for (int k = 0; k < 1000; ++k) {
      OperatingPoint op;
      op.speed_mps = std::pow(10.0, -3.0 + 5.0 * u(rng));
      op.slip_angle_rad = (u(rng) - 0.5) * 178.0 * units::kDegree;
      op.slip_ratio = -0.999 + 2.999 * u(rng);
      op.load_n = 100.0 * (0.01 + 3.0 * u(rng));
      op.path_curvature_per_m = u(rng) < 0.5 ? 0.0 : (u(rng) - 0.5) * 40.0;
      WearResult r;
      ASSERT_NE(model.evaluate(op, &r), EvalStatus::kInvalidInput);
      ASSERT_TRUE(std::isfinite(r.fx_n) && std::isfinite(r.fy_n) && std::isfinite(r.mz_nm)) << k;
      EXPECT_GT(r.wear_rate_kg_per_m, 0.0) << k;
      EXPECT_GE(r.wear_rate_kg_per_s, 0.0) << k;
      EXPECT_LE(std::hypot(r.fx_n, r.fy_n), sat_max * f.mu_m * op.load_n * (1.0 + 1e-9)) << k;
      EXPECT_GE(r.stick_fraction, 0.0);
      EXPECT_LE(r.stick_fraction, 1.0 + 1e-12);
      EXPECT_LT(r.max_root_iterations, model.solver(preset).options().max_root_iterations) << k;
    }
  }
}

// The marcher's SIMD packs of strips (the widest the CPU has, and SSE2 pairs) and one strip at a time
// are the same model: over straight and turn-slip points, with and without substeps, their results agree
// to the rounding of vector exp/log and to where the root tolerance stops an iteration.
TEST(BrushMarcher, SimdPacksAgreeWithOneStripAtATime) {
  const TireParams params;
  double worst_force = 0.0, worst_wear = 0.0, worst_fraction = 0.0;
  for (Preset preset : {Preset::kFast, Preset::kStandard, Preset::kFine})
    for (int lanes : {4, 2}) {
      BrushOptions packed = presetOptions(preset), single = packed;
      packed.max_simd_lanes = lanes;
      single.max_simd_lanes = 1;
      const BrushWearModel m_packed(params, packed), m_single(params, single);
      for (double alpha_deg : {0.0, 1.0, 6.0, 15.0})
        for (double kappa : {-0.2, 0.0, 0.05})
          for (double speed : {0.5, 5.0, 40.0})
            for (double curvature : {0.0, 0.2, 1.0 / 0.060}) {
              OperatingPoint op;
              op.speed_mps = speed;
              op.slip_angle_rad = alpha_deg * units::kDegree;
              op.slip_ratio = kappa;
              op.load_n = 100.0;
              op.path_curvature_per_m = curvature;
              WearResult p, s;
              m_packed.evaluate(op, &p);
              m_single.evaluate(op, &s);
              const double force_scale = std::max({std::hypot(s.fx_n, s.fy_n), 0.005 * op.load_n});
              worst_force = std::max({worst_force, std::fabs(p.fx_n - s.fx_n) / force_scale,
                                      std::fabs(p.fy_n - s.fy_n) / force_scale,
                                      std::fabs(p.mz_nm - s.mz_nm) / (force_scale * p.half_length_m)});
              worst_wear = std::max(worst_wear, std::fabs(p.wear_rate_kg_per_m / s.wear_rate_kg_per_m - 1.0));
              worst_fraction = std::max({worst_fraction, std::fabs(p.stick_fraction - s.stick_fraction),
                                         std::fabs(p.exact_stick_fraction - s.exact_stick_fraction)});
            }
    }
  std::printf("worst differences: force %.3g, wear %.3g, fraction %.3g\n", worst_force, worst_wear, worst_fraction);
  // Measured on AVX2 (glibc 2.36 libmvec): 4e-14 / 3e-15 / 2e-15; the bound leaves room for other libmvec builds.
  EXPECT_LT(worst_force, 1e-6);
  EXPECT_LT(worst_wear, 1e-6);
  EXPECT_LT(worst_fraction, 1e-6);
}

// A repeated point is not solved again, and its result is bit for bit what a model that never saw it solves.
TEST(WearModelRepeatedPoint, ReusesTheLastSolveOnlyForTheSamePointAndPreset) {
  const WearModel model(TireParams(), fastOptions());
  const auto same = [](const WearResult& a, const WearResult& b) {
    return a.fx_n == b.fx_n && a.fy_n == b.fy_n && a.mz_nm == b.mz_nm && a.wear_rate_kg_per_m == b.wear_rate_kg_per_m &&
           a.wear_rate_kg_per_s == b.wear_rate_kg_per_s && a.stick_fraction == b.stick_fraction &&
           a.slide_fraction == b.slide_fraction && a.exact_stick_fraction == b.exact_stick_fraction &&
           a.half_length_m == b.half_length_m && a.half_width_m == b.half_width_m &&
           a.max_root_iterations == b.max_root_iterations && a.root_iterations == b.root_iterations &&
           a.refined_substeps == b.refined_substeps;
  };
  const OperatingPoint a = rigPoint(0.3), b = rigPoint(0.31);
  WearResult first, again, other, fresh;
  model.evaluate(a, &first);
  EXPECT_FALSE(model.lastEvaluationReused());
  model.evaluate(a, &again);
  EXPECT_TRUE(model.lastEvaluationReused());
  WearModel(TireParams(), fastOptions()).evaluate(a, &fresh);
  EXPECT_TRUE(same(again, fresh));
  EXPECT_TRUE(same(first, fresh));
  model.evaluate(b, &other);
  EXPECT_FALSE(model.lastEvaluationReused());
  EXPECT_NE(other.fy_n, first.fy_n);
  // Below the low-speed threshold every speed is solved at the threshold: one solve, wear per time at its own speed.
  WearResult stand_a, stand_b;
  model.evaluate(rigPoint(0.0), &stand_a);
  model.evaluate(rigPoint(0.05), &stand_b);
  EXPECT_TRUE(model.lastEvaluationReused());
  EXPECT_EQ(stand_a.wear_rate_kg_per_s, 0.0);
  EXPECT_EQ(stand_b.wear_rate_kg_per_s, stand_b.wear_rate_kg_per_m * 0.05);
  // Another preset, a time budget (every solve is timed) or local fields: solved again.
  WearModel presets(TireParams(), fastOptions());
  presets.evaluate(a, &first);
  presets.setPreset(Preset::kStandard);
  presets.evaluate(a, &again);
  EXPECT_FALSE(presets.lastEvaluationReused());
  presets.setTimeBudget(1.0);
  presets.evaluate(a, &again);
  presets.evaluate(a, &again);
  EXPECT_FALSE(presets.lastEvaluationReused());
  presets.setTimeBudget(0.0);
  PatchFields fields;
  fields.resize(presets.solver(Preset::kStandard).nodesX(), presets.solver(Preset::kStandard).strips());
  presets.evaluate(a, &again);
  presets.evaluate(a, &again, &fields);
  EXPECT_FALSE(presets.lastEvaluationReused());
  EXPECT_FALSE(fields.pressure_pa.empty());
}

TEST(WearModelInput, InvalidPointsAreRejectedAndLeaveTheResultUntouched) {
  const WearModel model(TireParams(), fastOptions());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  WearResult r;
  r.fy_n = 123.0;
  for (auto mutate : std::vector<void (*)(OperatingPoint*)>{
           [](OperatingPoint* p) { p->speed_mps = -1.0; },
           [](OperatingPoint* p) { p->load_n = 0.0; },
           [](OperatingPoint* p) { p->slip_ratio = -1.0; },
           [](OperatingPoint* p) { p->slip_angle_rad = 0.5 * units::kPi; },
           [](OperatingPoint* p) { p->path_curvature_per_m = std::numeric_limits<double>::infinity(); }}) {
    OperatingPoint op = rigPoint(2.0);
    mutate(&op);
    EXPECT_EQ(model.evaluate(op, &r), EvalStatus::kInvalidInput);
  }
  OperatingPoint op = rigPoint(nan);
  EXPECT_EQ(model.evaluate(op, &r), EvalStatus::kInvalidInput);
  EXPECT_EQ(r.fy_n, 123.0);
}

TEST(WearModelInput, InvalidOptionsNameTheField) {
  auto message = [](WearModelOptions o) {
    std::string error;
    EXPECT_FALSE(o.validate(&error));
    return error;
  };
  WearModelOptions o;
  o.min_speed_mps = 0.0;
  EXPECT_NE(message(o).find("min_speed_mps"), std::string::npos);
  o = WearModelOptions();
  o.min_rolling_speed_mps = 1.0;  // above min_speed_mps
  EXPECT_NE(message(o).find("min_rolling_speed_mps"), std::string::npos);
  o = WearModelOptions();
  o.time_budget_s = -1e-6;
  EXPECT_NE(message(o).find("time_budget_s"), std::string::npos);
  o = WearModelOptions();
  o.budget_probe_interval = 0;
  EXPECT_NE(message(o).find("budget_probe_interval"), std::string::npos);
  o = WearModelOptions();
  o.timing_smoothing = 0.0;
  EXPECT_NE(message(o).find("timing_smoothing"), std::string::npos);
  EXPECT_THROW(WearModel(TireParams(), o), std::invalid_argument);
  WearModel model{TireParams(), WearModelOptions()};
  EXPECT_THROW(model.setTimeBudget(-1.0), std::invalid_argument);
  EXPECT_THROW(model.setTimeBudget(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(BrushOptionsValidation, RefinementAndShoulderPanelsNameTheField) {
  auto message = [](const BrushOptions& o) {
    std::string error;
    EXPECT_FALSE(o.validate(&error));
    return error;
  };
  BrushOptions o;
  o.grid.lateral_rule = LateralRule::kGaussShoulderPanels;
  o.grid.n_strips = 7;  // panels are mirrored pairs: even counts only
  EXPECT_NE(message(o).find("grid.n_strips"), std::string::npos);
  o.grid.n_strips = 4;  // fewer than one node per panel
  EXPECT_NE(message(o).find("grid.n_strips"), std::string::npos);
  o = BrushOptions();
  o.refinement.max_level = RefinementOptions::kMaxLevel + 1;
  EXPECT_NE(message(o).find("refinement.max_level"), std::string::npos);
  o = BrushOptions();
  o.refinement.node_budget = -1;
  EXPECT_NE(message(o).find("refinement.node_budget"), std::string::npos);
  o = BrushOptions();
  o.refinement.resolution = 0.0;
  EXPECT_NE(message(o).find("refinement.resolution"), std::string::npos);
  o = BrushOptions();
  o.refinement.damping_ratio = -0.1;
  EXPECT_NE(message(o).find("refinement.damping_ratio"), std::string::npos);
  o = BrushOptions();
  o.grid.entry_transit_periods = -1.0;
  EXPECT_NE(message(o).find("grid.entry_transit_periods"), std::string::npos);
  o = BrushOptions();
  o.grid.entry_grading = 1.0;  // the sine map degenerates at the edge
  EXPECT_NE(message(o).find("grid.entry_grading"), std::string::npos);
  for (int strips : {-1, GridSpec::kMaxStrips + 1}) {
    o = BrushOptions();
    o.grid.entry_strips = strips;
    EXPECT_NE(message(o).find("grid.entry_strips"), std::string::npos) << strips;
  }
  o = presetOptions(Preset::kStandard);
  o.grid.entry_strips = 13;  // shoulder panels take an even count
  EXPECT_NE(message(o).find("grid.entry_strips"), std::string::npos);
  o = BrushOptions();
  o.max_simd_lanes = 3;  // packs are 1, 2 or 4 strips wide
  EXPECT_NE(message(o).find("max_simd_lanes"), std::string::npos);
  EXPECT_THROW(BrushWearModel(TireParams(), o), std::invalid_argument);
  EXPECT_TRUE(presetOptions(Preset::kStandard).validate(nullptr));
}

// The entry-transient grid is used exactly where the element crosses the patch within
// entry_transit_periods natural periods 2 pi sqrt(m / k_x), k_x = phi (k_y0 + k_y1 Fz) (Eq 13), with the
// transit 2a/V_r from Eq 6; the switch speed is computed here from the parameters, independently of
// the model. Just below it the model equals one without the entry grid, just above it one that always
// uses it, and the two grids do differ there (else the check would be empty).
TEST(BrushEntryGrid, SwitchesAtTheTransitOfTheGivenNumberOfNaturalPeriods) {
  const TireParams params;
  BrushOptions off = presetOptions(Preset::kStandard);
  off.grid.entry_transit_periods = 0.0;
  off.grid.entry_strips = 0;
  BrushOptions on = off, always = off;
  on.grid.entry_transit_periods = 1.5;
  on.grid.entry_grading = always.grid.entry_grading = 0.98;
  on.grid.entry_strips = always.grid.entry_strips = 24;
  always.grid.entry_transit_periods = 1e9;
  const BrushWearModel model_off(params, off), model_on(params, on), model_always(params, always);

  OperatingPoint op;
  op.load_n = 100.0;
  op.path_curvature_per_m = 0.2;  // pure turn slip: the entry transient carries Fy
  const double kx = params.tread.phi * (params.tread.k_y0_pa_per_m + params.tread.k_y1_pa_per_m_n * op.load_n);
  const double period_s = 2.0 * units::kPi * std::sqrt(params.tread.m_kg_per_m2 / kx);
  const double switch_speed = 2.0 * params.footprint.halfLength(op.load_n) / (1.5 * period_s);  // V_r = V here
  for (double factor : {0.99, 1.01}) {
    op.speed_mps = factor * switch_speed;
    WearResult r_off, r_on, r_always;
    model_off.evaluate(op, &r_off);
    model_on.evaluate(op, &r_on);
    model_always.evaluate(op, &r_always);
    EXPECT_NE(r_off.fy_n, r_always.fy_n) << factor;
    EXPECT_EQ(r_on.fy_n, factor < 1.0 ? r_off.fy_n : r_always.fy_n) << factor;
    EXPECT_EQ(r_on.wear_rate_kg_per_m, factor < 1.0 ? r_off.wear_rate_kg_per_m : r_always.wear_rate_kg_per_m) << factor;
    EXPECT_EQ(r_on.mz_nm, factor < 1.0 ? r_off.mz_nm : r_always.mz_nm) << factor;
  }
}

// Fields are sized for the widest lateral grid (strips()); each evaluation says how many strips it used,
// and the strip centres are those of that grid's rule (mirror-symmetric here, y_e = 0).
TEST(BrushEntryGrid, FieldsCarryTheStripsOfTheGridUsed) {
  const TireParams params;
  const BrushWearModel standard(params, presetOptions(Preset::kStandard));
  const BrushOptions options = presetOptions(Preset::kStandard);
  ASSERT_GT(options.grid.entry_strips, options.grid.n_strips);
  EXPECT_EQ(standard.strips(), options.grid.entry_strips);
  PatchFields fields;
  fields.resize(standard.nodesX(), standard.strips());
  OperatingPoint op;
  op.load_n = 100.0;
  op.slip_angle_rad = 3.0 * units::kDegree;
  for (double speed_mps : {0.5, 40.0, 0.5}) {  // rig-like transit, entry transient, and back
    op.speed_mps = speed_mps;
    WearResult with_fields, without;
    standard.evaluate(op, &with_fields, &fields);
    standard.evaluate(op, &without);
    const int expected = speed_mps > 10.0 ? options.grid.entry_strips : options.grid.n_strips;
    EXPECT_EQ(fields.n_strips, expected) << speed_mps;
    for (int j = 0; j < expected; ++j)
      EXPECT_DOUBLE_EQ(fields.y_m[j], -fields.y_m[expected - 1 - j]) << speed_mps << " strip " << j;
    EXPECT_EQ(with_fields.mz_nm, without.mz_nm) << speed_mps;  // the fields do not change the model
    EXPECT_GT(fields.pressure_pa[fields.index(standard.nodesX() / 2, expected / 2)], 0.0) << speed_mps;
  }
}

TEST(WearModelPresets, NamesRoundTripAndUnknownIsRejected) {
  for (Preset p : kAllPresets) {
    Preset parsed = Preset::kFast;
    EXPECT_TRUE(parsePreset(presetName(p), &parsed));
    EXPECT_EQ(parsed, p);
    // The messages' list of choices is written out once (kPresetChoices): it must name every preset.
    EXPECT_NE(std::string(kPresetChoices).find(presetName(p)), std::string::npos) << presetName(p);
  }
  Preset untouched = Preset::kStandard;
  EXPECT_FALSE(parsePreset("ultra", &untouched));
  EXPECT_EQ(untouched, Preset::kStandard);
}

TEST(TurnSlipOrientationNames, LiteralAndFlippedOnly) {
  TurnSlipOrientation o = TurnSlipOrientation::kLiteral;
  EXPECT_TRUE(parseOrientation("flipped", &o));
  EXPECT_EQ(o, TurnSlipOrientation::kFlipped);
  EXPECT_STREQ(orientationName(o), "flipped");
  EXPECT_TRUE(parseOrientation("literal", &o));
  EXPECT_EQ(o, TurnSlipOrientation::kLiteral);
  EXPECT_STREQ(orientationName(o), "literal");
  for (const char* bad : {"both", "Literal", ""}) {
    EXPECT_FALSE(parseOrientation(bad, &o)) << bad;
    EXPECT_EQ(o, TurnSlipOrientation::kLiteral) << "untouched";
  }
}

}  // namespace
}  // namespace tread_wear
