// Measured side forces are screened by sign against the model before a fit (recording_checks.h): the model
// predicts about +50 N at these rig conditions (slip angle -0.17 rad, ISO axes), and no calibrated level or
// diagnosis term can flip that.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "common/rig_run.h"
#include "common/temp_file.h"
#include "tread_wear/cli/calibration_cli.h"
#include "tread_wear/fitting/recording_checks.h"
#include "tread_wear/io/params_io.h"

namespace tread_wear {
namespace {

const std::string kParams = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";

RunTable rigRuns(int n) {
  RunTable t;
  for (int i = 0; i < n; ++i) t.runs.push_back(rigRun(50.0 + i));
  return t;
}

TEST(SideForceSigns, OneRunOfTheWrongSignIsLeftOut) {
  RunTable t = rigRuns(6);
  t.runs[4].measured_side_force_n = -5.0;
  const std::vector<std::string> warnings =
      screenSideForceSigns(loadTireParams(kParams), TurnSlipOrientation::kLiteral, &t);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("run 5 (condition 'bench')"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("left out"), std::string::npos) << warnings[0];
  EXPECT_TRUE(std::isnan(t.runs[4].measured_side_force_n));
  EXPECT_EQ(t.runs[4].measured_wear_rate_kg_per_m, 6e-7) << "the run's wear stays";
  for (int i : {0, 1, 2, 3, 5}) EXPECT_EQ(t.runs[i].measured_side_force_n, 50.0 + i);
}

TEST(SideForceSigns, SmallPredictedForcesAreNotJudged) {
  RunTable t = rigRuns(4);
  for (RunRecord& r : t.runs) {  // straight, no slip angle: the model predicts ~0 N, noise may have either sign
    r.op.slip_angle_rad = 0.0;
    r.op.path_curvature_per_m = 0.0;
    r.measured_side_force_n = -0.5;
  }
  EXPECT_TRUE(screenSideForceSigns(loadTireParams(kParams), TurnSlipOrientation::kLiteral, &t).empty());
  EXPECT_EQ(t.runs[0].measured_side_force_n, -0.5);

  RunTable zero = rigRuns(4);  // zero has no sign: left to the tools' own check of the measurement
  zero.runs[1].measured_side_force_n = 0.0;
  EXPECT_TRUE(screenSideForceSigns(loadTireParams(kParams), TurnSlipOrientation::kLiteral, &zero).empty());
  EXPECT_EQ(zero.runs[1].measured_side_force_n, 0.0);
}

TEST(SideForceSigns, AnotherAxisConventionIsAnError) {
  RunTable t = rigRuns(6);
  for (RunRecord& r : t.runs) r.measured_side_force_n = -r.measured_side_force_n;  // SAE's y axis
  try {
    screenSideForceSigns(loadTireParams(kParams), TurnSlipOrientation::kLiteral, &t);
    FAIL() << "expected RunTableError";
  } catch (const RunTableError& e) {
    EXPECT_NE(std::string(e.what()).find("6 of 6 runs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ISO 8855"), std::string::npos) << e.what();
  }
}

// Before the screening, the calibration fitted such a table: mu_0 and mu_m at their lower bounds, Fy RMSER 122%.
TEST(SideForceSigns, CalibrateStopsOnAnotherAxisConvention) {
  const TempFile runs("# tread_wear run table v1\nspeed_mps,slip_angle_rad,load_n,side_force_n\n"
                      "2,-0.17,75,-50\n2,-0.17,75,-51\n2,-0.17,100,-62\n2,-0.26,75,-60\n",
                      ".csv");
  const TempFile json("", ".json");
  const char* argv[] = {"tread_wear_calibrate", "--params", kParams.c_str(), "--runs", runs.path().c_str(),
                        "--fit", "mu_0,mu_m", "--no-cv", "--json", json.path().c_str()};
  std::ostringstream out, err;
  EXPECT_EQ(runCalibrateCli(10, argv, out, err), 1);
  EXPECT_NE(err.str().find("axis convention"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace tread_wear
