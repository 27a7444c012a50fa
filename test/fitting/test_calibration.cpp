// Calibration of the brush wear model (calibration.h) on synthetic runs from known parameters, the parameter
// registry, and the CLI's handling of bad input. Coarse grids keep it fast: the synthetic data are generated
// on the same grid, so grid error does not enter the recovery.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tread_wear/cli/calibration_cli.h"
#include "tread_wear/fitting/calibration.h"
#include "tread_wear/report/calibration_report.h"

namespace tread_wear {
namespace {

constexpr double kDeg = M_PI / 180.0;

CalibrationOptions coarseOptions() {
  CalibrationOptions o;
  o.grid = {24, 4, 0.8};
  o.turn_slip_iterations = 1;
  return o;
}

// Table 3 conditions (7 distinct, the benchmark three times), measured values from `truth`.
RunTable syntheticRuns(const TireParams& truth, const CalibrationOptions& o) {
  const double rows[9][3] = {{1, 10, 75}, {2, 10, 75}, {3, 10, 75}, {2, 5, 75}, {2, 10, 75},
                             {2, 15, 75}, {2, 10, 50}, {2, 10, 75}, {2, 10, 100}};
  RunTable t;
  for (const auto& row : rows) {
    RunRecord r;
    r.op.speed_mps = row[0];
    r.op.slip_angle_rad = -row[1] * kDeg;
    r.op.path_curvature_per_m = 1.0 / 0.060;
    r.op.load_n = row[2];
    char id[64];
    std::snprintf(id, sizeof id, "v%g_a%g_fz%g", row[0], row[1], row[2]);
    r.condition_id = id;
    t.runs.push_back(r);
  }
  const auto pred = predictRuns(truth, t, o);
  for (size_t i = 0; i < t.runs.size(); ++i) {
    t.runs[i].measured_side_force_n = pred[i].first;
    t.runs[i].measured_wear_rate_kg_per_m = pred[i].second;
  }
  return t;
}

TEST(ParameterRegistry, CoversTireParamsAndRoundTrips) {
  // 10 footprint + 7 friction + 6 tread + 6 wear-law (w1..w4, T0, sigma_T) members.
  EXPECT_EQ(parameterRegistry().size(), 29u);
  TireParams p;
  for (const ParameterInfo& info : parameterRegistry()) {
    EXPECT_LT(info.lower, info.upper) << info.name;
    if (info.log_scale) {
      EXPECT_GT(info.lower, 0.0) << info.name;
    }
    const double v = getParameter(p, info.name);
    setParameter(&p, info.name, v * 1.5 + 1.0);
    EXPECT_DOUBLE_EQ(getParameter(p, info.name), v * 1.5 + 1.0) << info.name;
  }
  EXPECT_EQ(getParameter(TireParams{}, "k_y0"), TireParams{}.tread.k_y0_pa_per_m);
  EXPECT_THROW(getParameter(p, "k_z"), std::invalid_argument);
  EXPECT_THROW(parseParameterList("w1,bogus"), std::invalid_argument);
  EXPECT_EQ(parseParameterList(" w1, w2 ,w3"), (std::vector<std::string>{"w1", "w2", "w3"}));
}

TEST(Calibration, RecoversWearLawFromSyntheticRuns) {
  CalibrationOptions o = coarseOptions();
  TireParams truth;
  truth.wear.w1 = 0.5;
  truth.wear.w2 = 2.0;
  truth.wear.w3_kg_per_s_m2 = 0.2;
  truth.wear.w4_kg_per_s_m2 = 2e-3;
  const RunTable runs = syntheticRuns(truth, o);
  o.cross_validate = false;
  const CalibrationResult r = calibrate(TireParams{}, runs, o);
  ASSERT_TRUE(r.summary.usable) << r.summary.message;
  EXPECT_EQ(r.target, CalibrationTarget::kWear);
  // Noise-free data from the same model and grid; the tolerance covers the finite-difference Jacobian
  // (step 1e-3) and the solver's stopping tolerances.
  constexpr double kTol = 1e-3;
  EXPECT_NEAR(r.params.wear.w1, 0.5, kTol);
  EXPECT_NEAR(r.params.wear.w2, 2.0, kTol);
  EXPECT_NEAR(r.params.wear.w3_kg_per_s_m2 / 0.2, 1.0, kTol);
  EXPECT_NEAR(r.params.wear.w4_kg_per_s_m2 / 2e-3, 1.0, 1e-2);  // w4 is the weakest-identified term
  EXPECT_LT(r.fitted.rmser_wear, 1e-4);
  EXPECT_GT(r.initial.rmser_wear, 0.1);
  // Side force does not depend on the wear law.
  EXPECT_NEAR(r.fitted.rmser_side_force, r.initial.rmser_side_force, 1e-12);
}

TEST(Calibration, RecoversStiffnessWithCrossValidation) {
  CalibrationOptions o = coarseOptions();
  TireParams truth;
  truth.tread.k_y0_pa_per_m = 1.3e9;
  const RunTable runs = syntheticRuns(truth, o);
  o.fit = {"k_y0"};
  o.target = CalibrationTarget::kSideForce;
  const CalibrationResult r = calibrate(TireParams{}, runs, o);
  ASSERT_TRUE(r.summary.usable) << r.summary.message;
  EXPECT_NEAR(r.params.tread.k_y0_pa_per_m / 1.3e9, 1.0, 1e-3);
  // 7 folds (benchmark repeats share a condition_id); exact data: every held-out prediction is exact too.
  EXPECT_EQ(r.folds.size(), 7u);
  EXPECT_LT(r.cross_validated.rmser_side_force, 1e-3);
  EXPECT_FALSE(r.summary.parameters[0].atBound());
  const nlohmann::json j = nlohmann::json::parse(calibrationJson(r, {}));
  for (const char* key : {"rmser_side_force", "rmser_wear", "cv_rmser_side_force", "cv_rmser_wear", "parameters",
                          "correlations", "condition_number", "residuals", "termination"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["parameters"][0]["name"], "k_y0");
}

TEST(Calibration, PriorKeepsParameterNearFile) {
  CalibrationOptions o = coarseOptions();
  TireParams truth;
  truth.tread.k_y0_pa_per_m = 1.3e9;
  const RunTable runs = syntheticRuns(truth, o);
  o.fit = {"k_y0"};
  o.target = CalibrationTarget::kSideForce;
  o.cross_validate = false;
  o.prior_weight = 100.0;  // a 1% deviation from the file costs as much as one run off by 100%
  const CalibrationResult r = calibrate(TireParams{}, runs, o);
  ASSERT_TRUE(r.summary.usable);
  const double file = TireParams{}.tread.k_y0_pa_per_m;
  EXPECT_LT(std::abs(r.params.tread.k_y0_pa_per_m / file - 1.0), 0.05);
}

TEST(Calibration, RejectsBadOptions) {
  CalibrationOptions o = coarseOptions();
  o.fit = {"w1", "w1"};
  std::string err;
  EXPECT_FALSE(o.validate(&err));
  EXPECT_NE(err.find("twice"), std::string::npos);
  o.fit = {"w1"};
  o.prior_weight = -1.0;
  EXPECT_FALSE(o.validate(&err));
  EXPECT_NE(err.find("prior_weight"), std::string::npos);
  RunTable no_wear;
  no_wear.runs.push_back(RunRecord{});
  no_wear.runs.back().op.speed_mps = 1.0;
  no_wear.runs.back().op.load_n = 75.0;
  EXPECT_THROW(calibrate(TireParams{}, no_wear, coarseOptions()), std::invalid_argument);
}

TEST(CalibrateCli, BadRunTableGivesClearErrorAndExitCode) {
  const std::string path = std::string(::testing::TempDir()) + "bad_runs.csv";
  {
    std::ofstream f(path);
    f << "# tread_wear run table v1\nspeed_mps,slip_angle_rad\n2,abc\n";
  }
  const std::string json = std::string(::testing::TempDir()) + "out.json";
  const std::string params = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";
  const char* argv[] = {"tread_wear_calibrate", "--params", params.c_str(), "--runs", path.c_str(),
                        "--json", json.c_str()};
  std::ostringstream out, err;
  EXPECT_EQ(runCalibrateCli(7, argv, out, err), 1);
  EXPECT_NE(err.str().find("bad_runs.csv"), std::string::npos) << err.str();

  const char* usage[] = {"tread_wear_calibrate", "--params", params.c_str(), "--runs", path.c_str(),
                         "--json", json.c_str(), "--fit", "w9"};
  std::ostringstream out2, err2;
  EXPECT_EQ(runCalibrateCli(9, usage, out2, err2), 2);
  EXPECT_NE(err2.str().find("w9"), std::string::npos);
}

// --robust-se switches the standard errors to the HC3 sandwich (its coverage: test_least_squares) and says so in
// the report and the JSON; the fit itself is the same.
TEST(CalibrateCli, RobustStandardErrorsAreTheSameFitWithOtherErrorsAndSaySo) {
  const std::string params = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";
  const std::string runs = std::string(TREAD_WEAR_SOURCE_DIR) + "/data/paper/table3_runs.csv";
  nlohmann::json fits[2];
  for (int robust = 0; robust < 2; ++robust) {
    const std::string json = std::string(::testing::TempDir()) + "se" + std::to_string(robust) + ".json";
    const char* argv[] = {"tread_wear_calibrate", "--params", params.c_str(), "--runs", runs.c_str(), "--json",
                          json.c_str(), "--fit", "w1,w3", "--grid", "60,8", "--no-cv", "--robust-se"};
    std::ostringstream out, err;
    ASSERT_EQ(runCalibrateCli(12 + robust, argv, out, err), 0) << err.str();
    EXPECT_NE(out.str().find(robust ? "standard errors: HC3 sandwich" : "standard errors: classic"),
              std::string::npos)
        << out.str();
    std::ifstream f(json);
    fits[robust] = nlohmann::json::parse(f);
    EXPECT_EQ(fits[robust]["standard_errors"], robust ? "hc3" : "classic");
  }
  for (int k = 0; k < 2; ++k) {
    const nlohmann::json &classic = fits[0]["parameters"][k], &hc3 = fits[1]["parameters"][k];
    EXPECT_EQ(classic["value"], hc3["value"]) << classic["name"];
    EXPECT_GT(hc3["std_error"].get<double>(), 0.0);
    EXPECT_NE(classic["std_error"], hc3["std_error"]) << classic["name"];
  }
}

}  // namespace
}  // namespace tread_wear
