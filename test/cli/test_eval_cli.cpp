// The built tread_wear_eval and tread_wear_compare binaries on good and bad input: exit codes, stdout/stderr
// separation (nothing on stdout after an error), output equal to the in-process model at full precision, sign
// conventions, and Eq 23 load binning end to end.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/io/params_io.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/load_binning.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

const std::string kBin = TREAD_WEAR_BINARY_DIR;
const std::string kSrc = TREAD_WEAR_SOURCE_DIR;
const std::string kParams = kSrc + "/config/tires/grosch_wheel.yaml";
const std::string kHeader = "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n";

struct ToolRun {
  int rc;
  std::string out;
  std::string err;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string tempPath(const std::string& name) { return testing::TempDir() + "tread_wear_cli_" + name; }

/// Runs a shell command with stdin from text; captures stdout and stderr separately.
ToolRun run(const std::string& command, const std::string& stdin_text = "") {
  const std::string in = tempPath("in.csv"), out = tempPath("out.txt"), err = tempPath("err.txt");
  std::ofstream(in) << stdin_text;
  const int status = std::system((command + " < " + in + " > " + out + " 2> " + err).c_str());
  ToolRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::remove(in.c_str());
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

std::string eval(const std::string& args) { return kBin + "/tread_wear_eval --params " + kParams + " " + args; }

std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::istringstream cs(line);
    for (std::string cell; std::getline(cs, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

class Cli : public testing::Test {
 protected:
  void SetUp() override {
    for (const char* tool : {"tread_wear_eval", "tread_wear_compare"})
      ASSERT_TRUE(std::ifstream(kBin + "/" + tool).good()) << "build the tools first: " << kBin << "/" << tool;
  }
};

/// An output row carries the model's numbers exactly (round-trip precision): Fx, Fy, Mz, W_r, exact stick.
void expectRowEquals(const std::vector<std::string>& row, const WearResult& expected, int row_number) {
  EXPECT_EQ(std::stod(row[5]), expected.fx_n) << "row " << row_number;
  EXPECT_EQ(std::stod(row[6]), expected.fy_n) << "row " << row_number;
  EXPECT_EQ(std::stod(row[7]), expected.mz_nm) << "row " << row_number;
  EXPECT_EQ(std::stod(row[8]), expected.wear_rate_kg_per_m) << "row " << row_number;
  EXPECT_EQ(std::stod(row[12]), expected.exact_stick_fraction) << "row " << row_number;
}

TEST_F(Cli, EvalMatchesTheModelAtFullPrecision) {
  const std::string input = kHeader +
                            "2,-0.17453292519943295,0,0.06,75\n"  // Table 3 benchmark, rig as turn slip
                            "10,0.05,0,,3000\n"                   // straight, positive slip angle
                            "5,0,0.05,0,3000\n";                  // straight, driving slip
  const ToolRun r = run(eval("--preset fast -"), input);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto rows = csvRows(r.out);
  ASSERT_EQ(rows.size(), 4u);
  ASSERT_EQ(rows[0].size(), 13u);
  EXPECT_EQ(rows[0][6], "fy_n");
  WearModelOptions options;
  options.preset = Preset::kFast;
  const WearModel model(loadTireParams(kParams), options);
  const OperatingPoint ops[3] = {
      {2, -0.17453292519943295, 0, 1 / 0.06, 75}, {10, 0.05, 0, 0, 3000}, {5, 0, 0.05, 0, 3000}};
  for (int i = 0; i < 3; ++i) {
    WearResult expected;
    model.evaluate(ops[i], &expected);
    expectRowEquals(rows[i + 1], expected, i + 1);
  }
  // ISO 8855: the mirrored rig condition gives the paper's positive side force; a positive slip angle a
  // negative one; driving slip a positive Fx.
  EXPECT_GT(std::stod(rows[1][6]), 0.0);
  EXPECT_LT(std::stod(rows[2][6]), 0.0);
  EXPECT_GT(std::stod(rows[3][5]), 0.0);
  // Wear per time = W_r V (row 2: V = 10 m/s).
  EXPECT_DOUBLE_EQ(std::stod(rows[2][9]), 10.0 * std::stod(rows[2][8]));
}

// --preset fine meets the issue 4 bounds where standard does not: at the stick-slip burst condition of the road
// grid (Fz 150 N, kappa -0.2, V 0.5 m/s, straight; standard 7.6% low in W_r) and the Table 3 benchmark it is
// within 2% of the independent CVODE solver (--preset reference) in W_r and within 1% in Fx and Fy.
TEST_F(Cli, FinePresetMeetsTheAccuracyBoundsAgainstTheReferenceSolver) {
  const std::string input = kHeader +
                            "0.5,0,-0.2,0,150\n"
                            "2,-0.17453292519943295,0,0.06,75\n";
  const ToolRun fine = run(eval("--preset fine -"), input), reference = run(eval("--preset reference -"), input);
  ASSERT_EQ(fine.rc, 0) << fine.err;
  ASSERT_EQ(reference.rc, 0) << reference.err;
  const auto f = csvRows(fine.out), r = csvRows(reference.out);
  ASSERT_EQ(f.size(), 3u);
  ASSERT_EQ(r.size(), 3u);
  for (size_t i = 1; i < f.size(); ++i) {
    const double fx = std::stod(r[i][5]), fy = std::stod(r[i][6]), load = std::stod(r[i][4]);
    EXPECT_NEAR(std::stod(f[i][5]), fx, 0.01 * std::max(std::fabs(fx), 0.01 * load)) << "row " << i;
    EXPECT_NEAR(std::stod(f[i][6]), fy, 0.01 * std::max(std::fabs(fy), 0.01 * load)) << "row " << i;
    EXPECT_NEAR(std::stod(f[i][8]) / std::stod(r[i][8]), 1.0, 0.02) << "row " << i;
  }
}

TEST_F(Cli, GridOptionRunsTheMarcherAtThatGrid) {
  // --grid NXxNS: the marcher at that grid with the reference preset's other options, and WearModel's low-speed
  // convention (row 2: below min_speed_mps, evaluated there, wear per time with the true speed).
  const std::string input = kHeader + "0.5,0,-0.2,0,150\n0.05,0.05,0,0,100\n";
  const ToolRun r = run(eval("--grid 120x4 -"), input);
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto rows = csvRows(r.out);
  ASSERT_EQ(rows.size(), 3u);
  BrushOptions options = presetOptions(Preset::kReference);
  options.grid.n_x_steps = 120;
  options.grid.n_strips = 4;
  const BrushWearModel model(loadTireParams(kParams), options);
  const OperatingPoint ops[2] = {{0.5, 0, -0.2, 0, 150}, {WearModelOptions().min_speed_mps, 0.05, 0, 0, 100}};
  for (int i = 0; i < 2; ++i) {
    WearResult expected;
    model.evaluate(ops[i], &expected);
    expectRowEquals(rows[i + 1], expected, i + 1);
  }
  EXPECT_DOUBLE_EQ(std::stod(rows[2][9]), 0.05 * std::stod(rows[2][8]));
  EXPECT_NE(r.err.find("row 2"), std::string::npos) << "low-speed note expected: " << r.err;
  for (const char* bad : {"--grid 3x8", "--grid 80", "--grid 80x0", "--grid 80x8x", "--grid 80x8 --preset fast"})
    EXPECT_EQ(run(eval(std::string(bad) + " -"), input).rc, 2) << bad;
}

TEST_F(Cli, OrientationOnlyMattersOnACurvedPath) {
  const std::string input = kHeader + "2,-0.17453292519943295,0,0.06,75\n10,0.05,0,0,3000\n";
  const ToolRun literal = run(eval("--preset fast --orientation literal -"), input);
  const ToolRun flipped = run(eval("--preset fast --orientation flipped -"), input);
  ASSERT_EQ(literal.rc, 0);
  ASSERT_EQ(flipped.rc, 0);
  const auto a = csvRows(literal.out), b = csvRows(flipped.out);
  EXPECT_NE(a[1][6], b[1][6]) << "turn slip flips with the orientation";
  EXPECT_EQ(a[2], b[2]) << "straight rolling has no curvature to flip";
}

TEST_F(Cli, FileInputTemperatureAndStandstill) {
  const std::string file = tempPath("conditions.csv");
  std::ofstream(file) << "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,tread_temperature_c\n"
                         "0,0.05,0,0,3000,40\n";
  const ToolRun r = run(eval("--preset fast " + file));
  std::remove(file.c_str());
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto rows = csvRows(r.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][5], "40") << "input columns are echoed";
  EXPECT_EQ(std::stod(rows[1][10]), 0.0) << "no wear per time at standstill";
  EXPECT_GT(std::stod(rows[1][9]), 0.0) << "W_r is held at its low-speed value";
  EXPECT_NE(r.err.find("low-speed"), std::string::npos) << r.err;
}

TEST_F(Cli, EvalBadInputWritesNothingToStdout) {
  struct Case {
    std::string input;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {kHeader + "2,0.1,0,0,75\n2,0.1,0,0\n", {"row 2", "4 cells"}},
      {kHeader + "2,0.1,0,0,75\n2,x,0,0,75\n", {"row 2", "slip_angle_rad", "'x'"}},
      {kHeader + "2,0.1,0,0,75\n2,0.1,0,0,nan\n", {"row 2", "load_n"}},
      {kHeader + "2,0.1,0,0,75\n2,0.1,0,0,-75\n", {"row 2", "load_n", "> 0"}},
      {kHeader + "2,0.1,0,0,75\n2,1.6,0,0,75\n", {"row 2", "slip_angle_rad", "90 deg"}},
      {"speed_mps,slip_angle_rad,load_n\n2,0.1,75\n", {"missing column"}},
  };
  for (const Case& c : cases) {
    const ToolRun r = run(eval("--preset fast -"), c.input);
    EXPECT_EQ(r.rc, 1) << c.input;
    EXPECT_TRUE(r.out.empty()) << "partial output for:\n" << c.input << r.out;
    for (const std::string& f : c.fragments) EXPECT_NE(r.err.find(f), std::string::npos) << f << " not in " << r.err;
  }
}

TEST_F(Cli, UsageErrorsAndHelp) {
  const ToolRun help = run(kBin + "/tread_wear_eval --help");
  EXPECT_EQ(help.rc, 0);
  EXPECT_NE(help.out.find("usage: tread_wear_eval"), std::string::npos);
  EXPECT_EQ(run(kBin + "/tread_wear_eval -").rc, 2) << "--params is required";
  EXPECT_EQ(run(eval("--preset fastest -")).rc, 2);
  EXPECT_EQ(run(eval("--orientation sideways -")).rc, 2);
  EXPECT_EQ(run(eval("--bogus 1 -")).rc, 2);
  EXPECT_EQ(run(eval("")).rc, 2) << "a conditions file is required";
  const ToolRun missing = run(eval("/nonexistent/conditions.csv"));
  EXPECT_EQ(missing.rc, 1);
  EXPECT_NE(missing.err.find("/nonexistent/conditions.csv"), std::string::npos);
  const ToolRun bad_params =
      run(kBin + "/tread_wear_eval --params /nonexistent/tire.yaml -", kHeader + "2,0.1,0,0,75\n");
  EXPECT_EQ(bad_params.rc, 1);
  EXPECT_TRUE(bad_params.out.empty());
  EXPECT_NE(bad_params.err.find("/nonexistent/tire.yaml"), std::string::npos);
  const ToolRun compare_help = run(kBin + "/tread_wear_compare --help");
  EXPECT_EQ(compare_help.rc, 0);
  EXPECT_NE(compare_help.out.find("usage: tread_wear_compare"), std::string::npos);
  EXPECT_EQ(run(kBin + "/tread_wear_compare --params " + kParams).rc, 2) << "--runs is required";
}

TEST_F(Cli, CompareBinsTheLoadPerEq23) {
  // One run at 75 N with a 3 N standard deviation: 10 N bins at 65, 75, 85 N with normal shares (load_binning.h).
  const std::string runs = tempPath("runs.csv");
  const std::string out_csv = tempPath("compare.csv");
  std::ofstream(runs) << "# tread_wear run table v1\n"
                         "speed_mps,slip_angle_rad,path_radius_m,load_n,load_std_n,side_force_n,wear_rate_kg_per_m\n"
                         "2,-0.17453292519943295,0.06,75,3,49.5,0.62e-6\n";
  const ToolRun r = run(kBin + "/tread_wear_compare --params " + kParams + " --runs " + runs +
                    " --orientation literal --preset fast --csv " + out_csv);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("RMSER literal"), std::string::npos) << r.out;
  const auto rows = csvRows(slurp(out_csv));
  std::remove(runs.c_str());
  std::remove(out_csv.c_str());
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[0][10], "predicted_side_force_n");
  ASSERT_EQ(rows[0][13], "predicted_wear_rate_kg_per_m");
  // The same from the evaluator at the three bin loads, weighted by the normal shares computed here.
  const ToolRun bins = run(eval("--preset fast -"), kHeader + "2,-0.17453292519943295,0,0.06,65\n"
                                                          "2,-0.17453292519943295,0,0.06,75\n"
                                                          "2,-0.17453292519943295,0,0.06,85\n");
  ASSERT_EQ(bins.rc, 0) << bins.err;
  const auto b = csvRows(bins.out);
  const double phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }(5.0 / 3.0);
  const double phi_outer = 0.5 * std::erfc(-(15.0 / 3.0) / std::sqrt(2.0));
  const double centre = 2 * phi - 1;          // P(|z| < 5/3)
  const double side = (phi_outer - phi);       // P(5/3 < z < 5)
  const double total = centre + 2 * side;
  const double fy = (side * std::stod(b[1][6]) + centre * std::stod(b[2][6]) + side * std::stod(b[3][6])) / total;
  const double wr = (side * std::stod(b[1][8]) + centre * std::stod(b[2][8]) + side * std::stod(b[3][8])) / total;
  // Same model values, weights summed in a different order: agreement to rounding.
  EXPECT_NEAR(std::stod(rows[1][10]), fy, 1e-12 * std::fabs(fy));
  EXPECT_NEAR(std::stod(rows[1][13]), wr, 1e-12 * wr);
  EXPECT_NEAR(std::stod(rows[1][11]), fy / 49.5 - 1.0, 1e-12);
}

TEST_F(Cli, CompareBadRunTable) {
  const std::string runs = tempPath("bad_runs.csv");
  std::ofstream(runs) << "# tread_wear run table v1\nspeed_mps,slip_angle_rad,load_n\n2,0.1,abc\n";
  const ToolRun r = run(kBin + "/tread_wear_compare --params " + kParams + " --runs " + runs + " --preset fast");
  std::remove(runs.c_str());
  EXPECT_EQ(r.rc, 1);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find(":3:3: column 'load_n' = 'abc'"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tread_wear
