// The reference solver (CVODE, stick/slide events) against the marcher (BDF2, return mapping) on the
// 7 unique Table 3 rig conditions in both orientations, its fields output and its option validation.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "tread_wear/io/params_io.h"
#include "tread_wear/model/adhesion_wear.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/reference/reference_solver.h"
#include "tread_wear/studies/convergence_study.h"

namespace tread_wear {
namespace {

// Tolerances from the convergence study (docs/convergence.md, tread_wear_convergence): against the
// reference refined 4x (96 strips, rel_tol 1e-10) the marcher at 1600 x 64 is within 0.0105% (Fy),
// 0.012% (Mz) and 0.031% (W_r) on these conditions, the reference at its defaults within 0.003%,
// 0.005% and 0.008%. Sum of the two, rounded up by half: 0.02%, 0.025%, 0.06%.
constexpr double kFyTol = 2e-4;
constexpr double kMzTol = 2.5e-4;
constexpr double kWearTol = 6e-4;

TEST(ReferenceSolver, AgreesWithTheMarcherOnTable3Conditions) {
  const TireParams params;
  for (TurnSlipOrientation orientation : {TurnSlipOrientation::kLiteral, TurnSlipOrientation::kFlipped}) {
    ReferenceSolverOptions ro;
    ro.orientation = orientation;
    ReferenceBrushSolver reference(params, ro);
    BrushOptions mo;
    mo.grid.n_x_steps = 1600;
    mo.grid.n_strips = 64;
    mo.orientation = orientation;
    const BrushWearModel marcher(params, mo);
    for (const OperatingPoint& op : table3RigConditions()) {
      WearResult r, m;
      reference.evaluate(op, &r);
      marcher.evaluate(op, &m);
      const std::string where = std::string(orientation == TurnSlipOrientation::kLiteral ? "literal" : "flipped") +
                                " v " + std::to_string(op.speed_mps) + " alpha " + std::to_string(op.slip_angle_rad) +
                                " Fz " + std::to_string(op.load_n);
      EXPECT_NEAR(r.fy_n / m.fy_n, 1.0, kFyTol) << where;
      EXPECT_NEAR(r.mz_nm / m.mz_nm, 1.0, kMzTol) << where;
      EXPECT_NEAR(r.wear_rate_kg_per_m / m.wear_rate_kg_per_m, 1.0, kWearTol) << where;
      EXPECT_DOUBLE_EQ(r.wear_rate_kg_per_s, r.wear_rate_kg_per_m * op.speed_mps) << where;
      // Area fractions: the reference takes them from event times, the marcher from nodes of its grid
      // (a node in a band of width ~2a/1600 can fall either way; several bands per strip): 0.005.
      EXPECT_NEAR(r.stick_fraction, m.stick_fraction, 5e-3) << where;
      EXPECT_NEAR(r.stick_fraction + r.slide_fraction, 1.0, 1e-12) << where;
      EXPECT_LE(r.exact_stick_fraction, r.stick_fraction + 1e-12) << where;
      EXPECT_GT(r.fy_n, 0.0) << where;  // the rig's side force points to the track centre
      EXPECT_LE(reference.lastStats().max_events_strip, 20) << where;  // no chattering between modes
    }
  }
}

// Free rolling (no slip angle, slip ratio or path curvature): the road-sticking velocity is zero, so every
// element sticks undeflected through the patch. Exact answer: no force or moment, all of the patch in
// exact stick, and only the non-sliding wear term, W_r = w4 (2a)(2b) / V (Eq 19-20). The reference once
// threw here (at the trailing edge the static disc shrinks to the zero stick stress); the marcher presets
// must give the same limit.
TEST(ReferenceSolver, FreeRollingGivesNoForceAndOnlyTheNonSlidingWear) {
  const TireParams params;
  ReferenceBrushSolver reference(params, ReferenceSolverOptions());
  const BrushWearModel standard(params, presetOptions(Preset::kStandard));
  for (double load_n : {50.0, 150.0}) {
    for (double speed_mps : {0.5, 5.0, 40.0}) {
      OperatingPoint op;
      op.load_n = load_n;
      op.speed_mps = speed_mps;
      const double area_m2 = 4.0 * params.footprint.halfLength(load_n) * params.footprint.b_m;
      const double expected_kg_per_m = params.wear.w4_kg_per_s_m2 * area_m2 / speed_mps;
      WearResult r, m;
      ASSERT_NO_THROW(reference.evaluate(op, &r)) << "Fz " << load_n << " V " << speed_mps;
      standard.evaluate(op, &m);
      for (const WearResult* result : {&r, &m}) {
        const std::string where = std::string(result == &r ? "reference" : "standard") + " Fz " +
                                  std::to_string(load_n) + " V " + std::to_string(speed_mps);
        EXPECT_EQ(result->fx_n, 0.0) << where;
        EXPECT_EQ(result->fy_n, 0.0) << where;
        EXPECT_EQ(result->mz_nm, 0.0) << where;
        EXPECT_NEAR(result->wear_rate_kg_per_m / expected_kg_per_m, 1.0, 1e-9) << where;
        EXPECT_DOUBLE_EQ(result->exact_stick_fraction, 1.0) << where;
        EXPECT_DOUBLE_EQ(result->stick_fraction, 1.0) << where;
      }
    }
  }
}

// Free rolling where the pressure vanishes on part of a strip: at a light load the SUV file's short footprint with
// its pressure centre ahead of the contact centre (x_e = 3.16 mm against a = 5.9 mm at 50 N) leaves stretches of
// the edge strips unloaded, where the static disc and the zero stick stress coincide over an interval. The
// reference once stopped there ("root found at and very near t"). Exact answer as above: no force or moment, the
// whole patch in exact stick, and no sliding wear (w4 = 0): only the adhesion zone's free-rolling tread-band shear
// (model/adhesion_wear.h, closed form over the patch, tested on its own in test_adhesion_wear).
TEST(ReferenceSolver, FreeRollingOnAPartlyUnloadedStripStaysInStick) {
  const TireParams params = loadTireParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/suv_225_60_r18.yaml");
  ASSERT_EQ(params.wear.w4_kg_per_s_m2, 0.0);
  ReferenceBrushSolver reference(params, ReferenceSolverOptions());
  for (double speed_mps : {0.05, 1.0, 3.0}) {
    OperatingPoint op;
    op.load_n = 50.0;
    op.speed_mps = speed_mps;
    WearResult r;
    ASSERT_NO_THROW(reference.evaluate(op, &r)) << "V " << speed_mps;
    EXPECT_EQ(r.fx_n, 0.0) << "V " << speed_mps;
    EXPECT_EQ(r.fy_n, 0.0) << "V " << speed_mps;
    EXPECT_EQ(r.mz_nm, 0.0) << "V " << speed_mps;
    EXPECT_DOUBLE_EQ(r.exact_stick_fraction, 1.0) << "V " << speed_mps;
    EXPECT_DOUBLE_EQ(r.stick_fraction, 1.0) << "V " << speed_mps;
    const ContactPatch patch(params.footprint, op.load_n);
    const double adhesion_kg_per_m =
        AdhesionWear(params)
            .evaluate(op, patch, op.tipKinematics(TurnSlipOrientation::kLiteral), op.rollingSpeed())
            .wear_kg_per_m;
    ASSERT_GT(adhesion_kg_per_m, 0.0);
    EXPECT_NEAR(r.wear_rate_kg_per_m / adhesion_kg_per_m, 1.0, 1e-12) << "V " << speed_mps;
  }
}

TEST(ReferenceSolver, FieldsAtRequestedNodesArePhysical) {
  const TireParams params;
  ReferenceBrushSolver solver(params, ReferenceSolverOptions());
  const OperatingPoint op = table3RigConditions()[1];  // 2 m/s, 10 deg, 75 N
  const double a = params.footprint.halfLength(op.load_n);
  PatchFields fields;
  const int nx = 401;
  fields.resize(nx, solver.strips());
  for (int i = 0; i < nx; ++i) fields.x_m[i] = a * (1.0 - 2.0 * i / (nx - 1));
  WearResult r;
  solver.evaluate(op, &r, &fields);
  // Leading edge: p = 0, no friction; every strip pushes towards the track centre (Fy > 0).
  double fy = 0.0;
  const double b = params.footprint.b_m;
  for (int j = 0; j < solver.strips(); ++j) {
    EXPECT_DOUBLE_EQ(fields.tau_y_pa[fields.index(0, j)], 0.0);
    EXPECT_EQ(fields.pressure_pa[fields.index(0, j)], 0.0);
    EXPECT_LE(std::fabs(fields.y_m[j]), b);
    double strip = 0.0;
    for (int i = 0; i + 1 < nx; ++i)
      strip += 0.5 * (fields.tau_y_pa[fields.index(i, j)] + fields.tau_y_pa[fields.index(i + 1, j)]) *
               (fields.x_m[i] - fields.x_m[i + 1]);
    EXPECT_GT(strip, 0.0) << "strip " << j;
    fy += strip;
  }
  EXPECT_GT(fy, 0.0);
  // Friction never exceeds sat(p) mu_m p, and sliding opposes the friction stress.
  const SavkoorFriction friction(params.friction);
  for (int k = 0; k < nx * solver.strips(); ++k) {
    const double tau = std::hypot(fields.tau_x_pa[k], fields.tau_y_pa[k]);
    EXPECT_LE(
        tau,
        friction.saturation(fields.pressure_pa[k]) * params.friction.mu_m * fields.pressure_pa[k] * (1 + 1e-9) + 1e-6);
    const double vs_dot_tau = fields.v_sx_mps[k] * fields.tau_x_pa[k] + fields.v_sy_mps[k] * fields.tau_y_pa[k];
    EXPECT_LE(vs_dot_tau, 1e-12);
  }
}

TEST(ReferenceSolver, RejectsBadOptionsNamingTheField) {
  const TireParams params;
  struct Case {
    const char* field;
    void (*apply)(ReferenceSolverOptions*);
  };
  const Case cases[] = {
      {"n_strips", [](ReferenceSolverOptions* o) { o->n_strips = 0; }},
      {"n_strips", [](ReferenceSolverOptions* o) { o->n_strips = 1000; }},
      {"lateral_map_order", [](ReferenceSolverOptions* o) { o->lateral_map_order = 4; }},
      {"rel_tol", [](ReferenceSolverOptions* o) { o->rel_tol = 0.0; }},
      {"rel_tol", [](ReferenceSolverOptions* o) { o->rel_tol = NAN; }},
      {"abs_tol_factor", [](ReferenceSolverOptions* o) { o->abs_tol_factor = -1.0; }},
      {"stop_speed_mps", [](ReferenceSolverOptions* o) { o->stop_speed_mps = 1e-3; }},
      {"start_speed_mps", [](ReferenceSolverOptions* o) { o->start_speed_mps = 1e-7; }},
      {"static_tolerance", [](ReferenceSolverOptions* o) { o->static_tolerance = -1e-9; }},
      {"max_steps", [](ReferenceSolverOptions* o) { o->max_steps = 10; }},
      {"max_events_per_strip", [](ReferenceSolverOptions* o) { o->max_events_per_strip = 0; }},
  };
  for (const Case& c : cases) {
    ReferenceSolverOptions o;
    c.apply(&o);
    std::string error;
    EXPECT_FALSE(o.validate(&error)) << c.field;
    EXPECT_EQ(error.rfind(c.field, 0), 0u) << "message '" << error << "' should start with " << c.field;
    EXPECT_NE(error.find("must be"), std::string::npos) << error;
    EXPECT_THROW(ReferenceBrushSolver(params, o), std::invalid_argument) << c.field;
  }
  std::string error;
  EXPECT_TRUE(ReferenceSolverOptions().validate(&error)) << error;
}

TEST(ReferenceSolver, RejectsBadInputs) {
  TireParams bad_params;
  bad_params.tread.m_kg_per_m2 = -1.0;
  EXPECT_THROW(ReferenceBrushSolver(bad_params, ReferenceSolverOptions()), std::invalid_argument);

  const TireParams params;
  ReferenceBrushSolver solver(params, ReferenceSolverOptions());
  WearResult r;
  OperatingPoint op = table3RigConditions()[0];
  op.speed_mps = 0.0;
  EXPECT_THROW(solver.evaluate(op, &r), std::invalid_argument);
  op = table3RigConditions()[0];
  op.load_n = -5.0;
  EXPECT_THROW(solver.evaluate(op, &r), std::invalid_argument);
  op = table3RigConditions()[0];
  PatchFields fields;
  fields.resize(3, solver.strips());
  const double a = params.footprint.halfLength(op.load_n);
  fields.x_m = {0.0, a, -a};  // not descending
  EXPECT_THROW(solver.evaluate(op, &r, &fields), std::invalid_argument);
  fields.x_m = {2.0 * a, 0.0, -a};  // outside the patch
  EXPECT_THROW(solver.evaluate(op, &r, &fields), std::invalid_argument);
  PatchFields wrong_size;
  wrong_size.resize(3, solver.strips() + 1);
  EXPECT_THROW(solver.evaluate(op, &r, &wrong_size), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
