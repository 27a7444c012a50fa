// Run tables v1: the bundled Table 3 file against the printed table, wear from mass loss (Eq 2), covariates,
// write/read round trip, and one error per kind of bad input naming file, line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/temp_file.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/units.h"

namespace tread_wear {
namespace {

const std::string kTable3 = std::string(TREAD_WEAR_SOURCE_DIR) + "/data/paper/table3_runs.csv";
const std::string kMarker = "# tread_wear run table v1\n";

RunTable readText(const std::string& text) {
  TempFile f(text, ".csv");
  return readRunTable(f.path());
}

/// Expects a RunTableError whose message starts with "<file>:<location>" and contains each fragment.
void expectError(const std::string& text, const std::string& location, const std::vector<std::string>& fragments) {
  TempFile f(text, ".csv");
  try {
    readRunTable(f.path());
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const RunTableError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(f.path() + ":" + location, 0), 0u) << msg;
    for (const std::string& s : fragments) EXPECT_NE(msg.find(s), std::string::npos) << "'" << s << "' not in: " << msg;
  }
}

TEST(RunTable, Table3MatchesThePrintedTable) {
  const RunTable t = readRunTable(kTable3);
  ASSERT_EQ(t.runs.size(), 9u);
  // Printed Table 3 (v0 m/s, alpha deg, Fz N, Fy N, W_r g/km), benchmark-average row excluded.
  const double printed[9][5] = {{1, 10, 75, 50.60, 0.474}, {2, 10, 75, 50.48, 0.659}, {3, 10, 75, 52.50, 0.742},
                                {2, 5, 75, 21.79, 0.199},  {2, 10, 75, 48.78, 0.594}, {2, 15, 75, 62.59, 1.374},
                                {2, 10, 50, 39.09, 0.456}, {2, 10, 75, 49.30, 0.608}, {2, 10, 100, 57.99, 0.800}};
  for (int i = 0; i < 9; ++i) {
    const RunRecord& r = t.runs[i];
    EXPECT_EQ(r.op.speed_mps, printed[i][0]);
    EXPECT_NEAR(r.op.slip_angle_rad, -printed[i][1] * units::kPi / 180.0, 1e-15) << "row " << i;
    EXPECT_EQ(r.op.slip_ratio, 0.0);
    EXPECT_NEAR(r.op.path_curvature_per_m, 1.0 / 0.060, 1e-12);
    EXPECT_EQ(r.op.load_n, printed[i][2]);
    EXPECT_EQ(r.measured_side_force_n, printed[i][3]);
    EXPECT_NEAR(r.measured_wear_rate_kg_per_m, printed[i][4] * 1e-6, 1e-18) << "row " << i;
    EXPECT_TRUE(std::isnan(r.load_std_n));
    EXPECT_TRUE(std::isnan(r.op.tread_temperature_c));
  }
  // The benchmark condition appears three times under one id (7 unique conditions).
  EXPECT_EQ(t.runs[1].condition_id, "v2_a10_fz75");
  EXPECT_EQ(t.runs[4].condition_id, t.runs[1].condition_id);
  EXPECT_EQ(t.runs[7].condition_id, t.runs[1].condition_id);
  EXPECT_EQ(t.covariate_names, (std::vector<std::string>{"rsd_percent", "duration_s", "powder_g_per_min"}));
  EXPECT_EQ(t.text_covariate_names, (std::vector<std::string>{"group", "run_label"}));
  EXPECT_EQ(t.runs[3].covariates[0], 15.2);
  EXPECT_EQ(t.runs[3].covariates[1], 897.0);
  EXPECT_EQ(t.runs[8].text_covariates[0], "load");
  EXPECT_EQ(t.runs[8].text_covariates[1], "load_100");
}

TEST(RunTable, WearFromMassLossDistanceOrDuration) {
  // Eq 2: W_r = dm/(v0 t). 2 m/s for 450 s = 900 m; 0.45 g over 900 m = 0.5 mg/m = 5e-7 kg/m.
  const RunTable t = readText(kMarker +
                              "speed_mps,slip_angle_rad,load_n,mass_loss_kg,distance_m,duration_s\n"
                              "2,0.1,75,0.45e-3,,450\n"
                              "2,0.1,75,0.45e-3,900,\n"
                              "2,0.1,75,,,450\n");
  EXPECT_NEAR(t.runs[0].measured_wear_rate_kg_per_m, 5e-7, 1e-20);
  EXPECT_NEAR(t.runs[1].measured_wear_rate_kg_per_m, 5e-7, 1e-20);
  EXPECT_TRUE(std::isnan(t.runs[2].measured_wear_rate_kg_per_m));
  EXPECT_TRUE(std::isnan(t.runs[0].measured_side_force_n));
  // The derivation inputs stay available as covariates.
  EXPECT_EQ(t.covariate_names, (std::vector<std::string>{"mass_loss_kg", "distance_m", "duration_s"}));
  EXPECT_TRUE(std::isnan(t.runs[0].covariates[1]));
}

TEST(RunTable, OptionalColumnsAndDefaults) {
  const RunTable t = readText(kMarker + "# a comment\n\n"
                              "speed_mps , slip_angle_rad,load_n,load_mean_n,load_std_n,path_radius_m,slip_ratio,"
                              "tread_temperature_c,cycle_id,run_order,note\n"
                              "3,-0.05,80,78.5,4.2,,0.02,41.5,2,7,\"dry, warm\"\n"
                              "3,-0.05,80,,,-25,,,,,plain\n");
  const RunRecord& a = t.runs[0];
  EXPECT_EQ(a.op.load_n, 78.5) << "load_mean_n overrides load_n";
  EXPECT_EQ(a.load_std_n, 4.2);
  EXPECT_EQ(a.op.path_curvature_per_m, 0.0) << "empty radius = straight";
  EXPECT_EQ(a.op.slip_ratio, 0.02);
  EXPECT_EQ(a.op.tread_temperature_c, 41.5);
  EXPECT_EQ(a.cycle_id, 2);
  EXPECT_EQ(a.run_order, 7);
  EXPECT_EQ(a.text_covariates[0], "dry, warm");
  EXPECT_FALSE(a.condition_id.empty());
  const RunRecord& b = t.runs[1];
  EXPECT_EQ(b.op.load_n, 80.0);
  EXPECT_EQ(b.op.path_curvature_per_m, -1.0 / 25.0) << "negative radius = right turn (ISO)";
  EXPECT_EQ(b.cycle_id, -1);
  EXPECT_EQ(b.run_order, -1);
  EXPECT_NE(a.condition_id, b.condition_id) << "default ids follow the conditions";
}

TEST(RunTable, WriteReadRoundTrip) {
  RunTable t = readRunTable(kTable3);
  t.runs[0].load_std_n = 3.25;
  t.runs[0].cycle_id = 1;
  t.runs[0].op.tread_temperature_c = 44.0;
  t.runs[2].text_covariates[1] = "label, with \"quotes\"";
  TempFile out("", ".csv");
  writeRunTable(t, out.path(), "round trip\nof Table 3");
  const RunTable u = readRunTable(out.path());
  ASSERT_EQ(u.runs.size(), t.runs.size());
  EXPECT_EQ(u.covariate_names, t.covariate_names);
  EXPECT_EQ(u.text_covariate_names, t.text_covariate_names);
  for (std::size_t i = 0; i < t.runs.size(); ++i) {
    const RunRecord& a = t.runs[i];
    const RunRecord& b = u.runs[i];
    EXPECT_EQ(b.op.speed_mps, a.op.speed_mps);
    EXPECT_EQ(b.op.slip_angle_rad, a.op.slip_angle_rad);
    // The file stores the radius 1/c; 1/(1/c) may differ from c by one rounding.
    EXPECT_NEAR(b.op.path_curvature_per_m, a.op.path_curvature_per_m, 1e-14 * std::fabs(a.op.path_curvature_per_m));
    EXPECT_EQ(b.op.load_n, a.op.load_n);
    EXPECT_EQ(b.measured_side_force_n, a.measured_side_force_n);
    EXPECT_EQ(b.measured_wear_rate_kg_per_m, a.measured_wear_rate_kg_per_m);
    EXPECT_EQ(b.condition_id, a.condition_id);
    EXPECT_EQ(b.covariates, a.covariates);
    EXPECT_EQ(b.text_covariates, a.text_covariates);
    EXPECT_EQ(b.cycle_id, a.cycle_id);
  }
  EXPECT_EQ(u.runs[0].load_std_n, 3.25);
  EXPECT_EQ(u.runs[0].op.tread_temperature_c, 44.0);
}

const std::string kHeader = "speed_mps,slip_angle_rad,load_n,side_force_n\n";

TEST(RunTable, Errors) {
  EXPECT_THROW(readRunTable("/nonexistent/runs.csv"), RunTableError);
  expectError("", "", {"empty file", "marker"});
  expectError(kHeader + "2,0.1,75,40\n", "1:", {"missing marker line"});
  expectError("# tread_wear run table v2\n" + kHeader, "1:", {"unsupported", "v1"});
  expectError(kMarker + "# only comments\n", "2:", {"no header"});
  expectError(kMarker + kHeader, "2:", {"no runs"});
  expectError(kMarker + "speed_mps,load_n\n2,75\n", "2:", {"missing required column 'slip_angle_rad'"});
  expectError(kMarker + "speed_mps,slip_angle_rad,load_n,load_n\n", "2:", {"'load_n' appears twice"});
  expectError(kMarker + kHeader + "2,0.1,75,40\n2,0.1,75\n", "4:", {"3 cells", "header has 4"});
  expectError(kMarker + kHeader + "2,abc,75,40\n", "3:2:", {"'slip_angle_rad' = 'abc'", "finite number"});
  expectError(kMarker + kHeader + "2,nan,75,40\n", "3:2:", {"slip_angle_rad", "finite number"});
  expectError(kMarker + kHeader + "2,0.1,inf,40\n", "3:3:", {"load_n", "finite number"});
  expectError(kMarker + kHeader + "2,0.1,-75,40\n", "3:3:", {"load_n", "-75", "> 0"});
  expectError(kMarker + kHeader + "2,10,75,40\n", "3:2:", {"slip_angle_rad", "pi/2", "degrees"});
  expectError(kMarker + kHeader + "-1,0.1,75,40\n", "3:1:", {"speed_mps", ">= 0"});
  expectError(kMarker + kHeader + ",0.1,75,40\n", "3:1:", {"speed_mps", "required"});
  expectError(kMarker + kHeader + "2,0.1,75,forty\n", "3:4:", {"side_force_n", "finite number"});
  expectError(kMarker + "speed_mps,slip_angle_rad,load_n,mass_loss_kg\n2,0.1,75,1e-4\n", "3:4:",
              {"mass_loss_kg", "distance_m or duration_s"});
  expectError(kMarker + "speed_mps,slip_angle_rad,load_n,wear_rate_kg_per_m,mass_loss_kg,distance_m\n"
                        "2,0.1,75,1e-6,1e-4,900\n",
              "3:4:", {"wear_rate_kg_per_m", "disagrees"});
  expectError(kMarker + "speed_mps,slip_angle_rad,load_n,cycle_id\n2,0.1,75,1.5\n", "3:4:", {"cycle_id", "integer"});
  expectError(kMarker + "speed_mps,slip_angle_rad,load_n,note\n2,0.1,75,\"open\n", "3:", {"unterminated quote"});
  // A binary file's bytes are named, not echoed.
  expectError(kMarker + kHeader + "2,0.1,75," + std::string(1, '\0') + "\x01\n", "3:",
              {"control character 0x00 at byte 10", "not a text CSV"});
}

}  // namespace
}  // namespace tread_wear
