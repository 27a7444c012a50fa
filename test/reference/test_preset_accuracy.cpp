// Measured error bounds of the fast, standard and fine presets (docs/performance.md) hold on a modest grid
// of conditions against the fine reference: the marcher's 'reference' preset (1600 x 64), which agrees
// with the CVODE ReferenceBrushSolver within 0.02% on the rig grid and within 0.18% (Fx, Fy), 1.9% (Mz),
// 0.8% (W_r) and 0.008 (fractions) on the road grid (docs/performance.md). The bounds are the whole-grid maxima of the
// accuracy study, rounded up; the grid here is the Table 3 rig set plus a road subset that contains the study's worst
// conditions. Error scales: tread_wear/reference/solver_errors.h (F relative to max(|F_ref|, 0.05 |F_ref vector|,
// 0.005 Fz); Mz relative to max(|Mz_ref|, a times that force floor); W_r relative; fractions absolute).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../../bench/bench_conditions.h"  // the rig grid and the random road points of the accuracy study
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/solver_errors.h"

namespace tread_wear {
namespace {

struct Bounds {
  double force, mz, wear, fraction;
};

using bench::Condition;

std::vector<Condition> roadCases() {
  // {Fz [N], alpha [deg], kappa, V [m/s], curvature [1/m]}
  const double rows[][5] = {{150, 0, -0.2, 0.5, 0},  {50, 0, -0.05, 40, 0.2}, {50, 0, 0.05, 40, 0.2},
                            {100, 3, 0, 5, 0.2},     {100, 10, 0, 5, 0},      {100, 25, 0, 20, 0.2},
                            {150, 6, 0.2, 20, 0},    {50, 15, -0.2, 0.5, 0.2}, {100, 1, 0.05, 40, 0},
                            {150, 10, -0.05, 5, 0.2}, {50, 25, 0.2, 40, 0},   {100, 0, 0.2, 5, 0},
                            {150, 0, -0.05, 0.5, 0.2}, {150, 0, 0, 40, 0.2},   {150, 1, 0, 40, 0.2},
                            {150, 0, 0.05, 0.5, 0},  {50, 0, 0.2, 5, 0},     {100, 0, 0, 5, 0.2},
                            {50, 6, -0.05, 5, 0},    {100, 15, 0.2, 0.5, 0},  {150, 6, -0.2, 5, 0}};
  std::vector<Condition> out;
  for (const auto& r : rows) {
    Condition c;
    c.op.load_n = r[0];
    c.op.slip_angle_rad = r[1] * units::kDegree;
    c.op.slip_ratio = r[2];
    c.op.speed_mps = r[3];
    c.op.path_curvature_per_m = r[4];
    out.push_back(c);
  }
  return out;
}

void checkPreset(Preset preset, const std::vector<Condition>& cases, const Bounds& bounds) {
  const TireParams params;
  for (const Condition& c : cases) {
    const BrushWearModel ref(params, presetOptions(Preset::kReference, c.orientation));
    const BrushWearModel model(params, presetOptions(preset, c.orientation));
    WearResult r0, r;
    ref.evaluate(c.op, &r0);
    model.evaluate(c.op, &r);
    const SolverErrors e = solverErrors(r0, r, c.op.load_n);
    const std::string where = std::string(presetName(preset)) + " at Fz=" + std::to_string(c.op.load_n) +
                              " alpha=" + std::to_string(c.op.slip_angle_rad) +
                              " kappa=" + std::to_string(c.op.slip_ratio) + " V=" + std::to_string(c.op.speed_mps) +
                              " c=" + std::to_string(c.op.path_curvature_per_m);
    EXPECT_LE(e.fx, bounds.force) << where;
    EXPECT_LE(e.fy, bounds.force) << where;
    EXPECT_LE(e.mz, bounds.mz) << where;
    EXPECT_LE(e.wear, bounds.wear) << where;
    EXPECT_LE(e.stick, bounds.fraction) << where;
    EXPECT_LE(e.exact_stick, bounds.fraction) << where;
  }
}

// Bounds: docs/performance.md, "Accuracy" (whole-grid maxima, rounded up). On the rig, standard meets
// the issue 4 targets (F and Mz 1%, W_r 2%, fractions 0.02), so those are asserted; on the road grid
// it meets them for Fx and Fy (0.37% and 0.67% with the entry-transient grid) but not for Mz (1.8% with
// 24 strips on the entry-transient grid, 6.6% with 12), W_r and the fractions, and the measured maxima
// are asserted.
TEST(PresetAccuracy, StandardOnTable3Rig) {
  checkPreset(Preset::kStandard, bench::rigConditions(), {0.01, 0.01, 0.02, 0.02});
}
TEST(PresetAccuracy, StandardOnRoadGrid) { checkPreset(Preset::kStandard, roadCases(), {0.007, 0.02, 0.09, 0.03}); }
TEST(PresetAccuracy, FastOnTable3Rig) { checkPreset(Preset::kFast, bench::rigConditions(), {0.015, 0.04, 0.02, 0.02}); }
TEST(PresetAccuracy, FastOnRoadGrid) { checkPreset(Preset::kFast, roadCases(), {0.02, 0.06, 0.19, 0.07}); }
// fine meets the issue 4 bounds on both grids (whole road grid against the marcher reference: Fx 0.11%,
// Fy 0.17%, Mz 0.54%, W_r 1.48%, stick 0.005, exact stick 0.013), so those bounds are asserted on both.
TEST(PresetAccuracy, FineOnTable3Rig) { checkPreset(Preset::kFine, bench::rigConditions(), {0.01, 0.01, 0.02, 0.02}); }
TEST(PresetAccuracy, FineOnRoadGrid) { checkPreset(Preset::kFine, roadCases(), {0.01, 0.01, 0.02, 0.02}); }
// ... and between the grid's points: on 40 points drawn inside the road grid's envelope (bench::randomRoadConditions;
// 7000 such points in docs/performance.md, W_r at most 1.95%).
TEST(PresetAccuracy, FineBetweenTheRoadGridPoints) {
  checkPreset(Preset::kFine, bench::randomRoadConditions(100.0, 40, 2026), {0.01, 0.01, 0.02, 0.02});
}

// The presets are ordered: on the Table 3 rig conditions standard is at least as accurate as fast in
// W_r summed over the grid (a refinement that did not help would be a wasted preset).
TEST(PresetAccuracy, StandardImprovesOnFastForWearOnTheRig) {
  const TireParams params;
  double err_fast = 0.0, err_standard = 0.0;
  for (const Condition& c : bench::rigConditions()) {
    WearResult r0, rf, rs;
    BrushWearModel(params, presetOptions(Preset::kReference, c.orientation)).evaluate(c.op, &r0);
    BrushWearModel(params, presetOptions(Preset::kFast, c.orientation)).evaluate(c.op, &rf);
    BrushWearModel(params, presetOptions(Preset::kStandard, c.orientation)).evaluate(c.op, &rs);
    err_fast += std::fabs(rf.wear_rate_kg_per_m / r0.wear_rate_kg_per_m - 1.0);
    err_standard += std::fabs(rs.wear_rate_kg_per_m / r0.wear_rate_kg_per_m - 1.0);
  }
  EXPECT_LT(err_standard, err_fast);
}

// Local step refinement (BrushOptions::refinement) at the stick-slip condition of the road grid (Grosch
// wheel, Fz 150 N, straight, kappa -0.2, V 0.5 m/s): sliding just above v_m on the velocity-weakening
// branch makes the elements slip in bursts much shorter than an x step (docs/performance.md).
// Measured against the fine reference: the standard grid without refinement is off by 17.7% in W_r and
// 0.067 in the stick fraction; the standard preset (refining only unstable sliding, damping ratio 0)
// by 7.6% and 0.025; refining all sliding below critical damping (damping ratio 1, with a budget of
// 2160 substeps: it takes 1092) by 2.4% and 0.003.
// Asserted: each step of refinement at least halves the W_r error, and the fuller one meets the issue's
// stick-fraction bound (0.02) and W_r within 2.5%; the substeps stay within the node budget, and a
// refinement that is off adds none.
TEST(PresetAccuracy, RefinementResolvesStickSlipBursts) {
  const TireParams params;
  OperatingPoint op;
  op.load_n = 150.0;
  op.slip_ratio = -0.2;
  op.speed_mps = 0.5;
  const BrushOptions standard = presetOptions(Preset::kStandard);
  BrushOptions fixed = standard, full = standard;
  fixed.refinement.max_level = 0;
  full.refinement.damping_ratio = 1.0;
  full.refinement.node_budget = 2160;
  WearResult r0, rs, rf, rfull;
  BrushWearModel(params, presetOptions(Preset::kReference)).evaluate(op, &r0);
  BrushWearModel(params, standard).evaluate(op, &rs);
  BrushWearModel(params, fixed).evaluate(op, &rf);
  BrushWearModel(params, full).evaluate(op, &rfull);
  auto wearError = [&](const WearResult& r) { return std::fabs(r.wear_rate_kg_per_m / r0.wear_rate_kg_per_m - 1.0); };
  EXPECT_LT(wearError(rs), 0.5 * wearError(rf));
  EXPECT_LT(wearError(rfull), 0.5 * wearError(rs));
  EXPECT_LE(wearError(rfull), 0.025);
  EXPECT_LE(std::fabs(rfull.stick_fraction - r0.stick_fraction), 0.02);
  EXPECT_LT(std::fabs(rs.stick_fraction - r0.stick_fraction), 0.5 * std::fabs(rf.stick_fraction - r0.stick_fraction));
  EXPECT_GT(rs.refined_substeps, 0);
  EXPECT_LE(rs.refined_substeps, standard.refinement.node_budget);
  EXPECT_LE(rfull.refined_substeps, full.refinement.node_budget);
  EXPECT_EQ(rf.refined_substeps, 0);
}

// The node budget bounds the work: with a small budget the substeps never exceed it (a refined step
// takes 2^level substeps, so a budget of 2 still allows one).
TEST(PresetAccuracy, RefinementRespectsTheNodeBudget) {
  OperatingPoint op;
  op.load_n = 150.0;
  op.slip_ratio = -0.2;
  op.speed_mps = 0.5;
  BrushOptions o = presetOptions(Preset::kStandard);
  for (int budget : {2, 7, 64}) {
    o.refinement.node_budget = budget;
    WearResult r;
    BrushWearModel(TireParams(), o).evaluate(op, &r);
    EXPECT_LE(r.refined_substeps, budget);
    EXPECT_GT(r.refined_substeps, 0);
  }
}

}  // namespace
}  // namespace tread_wear
