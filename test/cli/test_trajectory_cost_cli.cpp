// tread_wear_trajectory_cost in-process (runTrajectoryCostCli): usage errors, the CSV reader's errors naming line
// and column, a per-trajectory status naming the bad sample, a constant-state trajectory's cost against the wear
// model called directly, the optional grade column, the node's wheel file as the source of the tires, and
// --generate piped into --compare.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/cli/trajectory_cost_cli.h"
#include "tread_wear/io/csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/vehicle_params_io.h"

namespace tread_wear {
namespace {

const std::string kSrc = TREAD_WEAR_SOURCE_DIR;
const std::string kVehicle = kSrc + "/config/vehicle_passenger_car.yaml";
const std::string kTire = kSrc + "/config/tires/passenger_205_55_r16.yaml";

struct ToolRun {
  int rc;
  std::string out, err;
};

ToolRun run(std::vector<std::string> args, const std::string& stdin_text = "") {
  args.insert(args.begin(), "tread_wear_trajectory_cost");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::istringstream in(stdin_text);
  std::ostringstream out, err;
  const int rc = runTrajectoryCostCli(static_cast<int>(argv.size()), argv.data(), in, out, err);
  return {rc, out.str(), err.str()};
}

/// Data rows of the tool's CSV as cells, header first.
std::vector<std::vector<std::string>> rows(const std::string& text) {
  std::vector<std::vector<std::string>> result;
  std::istringstream in(text);
  std::string line, error;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    EXPECT_TRUE(csv::splitLine(line, &cells, &error)) << error;
    result.push_back(cells);
  }
  return result;
}

double cell(const std::vector<std::vector<std::string>>& table, std::size_t row, const std::string& column) {
  const int c = csv::findColumn(table[0], column);
  EXPECT_GE(c, 0) << column;
  return std::stod(table[row][static_cast<std::size_t>(c)]);
}

TEST(TrajectoryCostCli, UsageErrors) {
  EXPECT_EQ(run({"--help"}).rc, 0);
  EXPECT_NE(run({"--help"}).out.find("usage: tread_wear_trajectory_cost"), std::string::npos);
  EXPECT_EQ(run({"--tire", kTire, "-"}).rc, 2);                                      // no --vehicle
  EXPECT_EQ(run({"--vehicle", kVehicle, "-"}).rc, 2);                                // no tire
  EXPECT_EQ(run({"--vehicle", kVehicle, "--tire", kTire, "--wheels", "w", "-"}).rc, 2);  // both
  EXPECT_EQ(run({"--vehicle", kVehicle, "--tire", kTire, "--map", "--compare", "-"}).rc, 2);
  EXPECT_EQ(run({"--vehicle", kVehicle, "--tire", kTire, "--preset", "coarse", "-"}).rc, 2);
}

TEST(TrajectoryCostCli, ConstantStateCostsTheWheelModelsRateTimesDuration) {
  // Straight at 20 m/s for 3 s: each wheel's wear is its WearModel rate at the vehicle model's state times 3 s.
  const std::string csv_text =
      "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\n"
      "cruise,0,20,0,0\ncruise,1.5,20,0,0\ncruise,3,20,0,0\n"
      "reverse,0,5,0,0\nreverse,1,-1,0,0\n";
  const ToolRun r = run({"--vehicle", kVehicle, "--tire", kTire, "--preset", "fast", "-"}, csv_text);
  EXPECT_EQ(r.rc, 1) << r.err;  // one trajectory could not be evaluated
  const auto table = rows(r.out);
  ASSERT_EQ(table.size(), 3u) << r.out;
  EXPECT_EQ(table[1][0], "cruise");
  EXPECT_EQ(table[1][1], "ok");
  const VehicleModel vehicle(loadVehicleParams(kVehicle));
  VehicleState state;
  vehicle.evaluate({20.0, 0.0, 0.0}, &state);
  WearModelOptions options;
  options.preset = Preset::kFast;
  const WearModel model(loadTireParams(kTire), options);
  double total = 0.0;
  for (int i = 0; i < kWheelCount; ++i) {
    const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
    OperatingPoint op;
    op.load_n = w.load_n;
    op.speed_mps = w.speed_mps;
    op.slip_angle_rad = w.slip_angle_rad;
    op.slip_ratio = w.slip_ratio;
    WearResult result;
    model.evaluate(op, &result);
    const double expected = 3.0 * result.wear_rate_kg_per_s;
    EXPECT_NEAR(cell(table, 1, std::string("wear_") + wheelName(i) + "_kg"), expected, expected * 1e-12);
    total += expected;
  }
  EXPECT_NEAR(cell(table, 1, "total_wear_kg"), total, total * 1e-12);
  EXPECT_NEAR(cell(table, 1, "distance_m"), 60.0, 1e-9);
  EXPECT_EQ(table[2][1], "bad_input");
  EXPECT_NE(table[2].back().find("sample 1: speed_mps = -1: must be >= 0"), std::string::npos) << table[2].back();
  EXPECT_NE(r.err.find("trajectory reverse: bad_input"), std::string::npos) << r.err;
}

TEST(TrajectoryCostCli, CsvErrorsNameTheLineAndColumn) {
  const std::vector<std::string> args = {"--vehicle", kVehicle, "--tire", kTire, "--preset", "fast", "-"};
  ToolRun r = run(args, "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\na,0,nan,0,0\n");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("line 2: column speed_mps: 'nan' is not a finite number"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  r = run(args, "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m,grade\na,0,1,0,0,0.1\n");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("line 1: column grade: name it grade_rad"), std::string::npos) << r.err;
  r = run(args, "trajectory_id,time_s,speed_mps,accel_mps2\n");
  EXPECT_NE(r.err.find("line 1: missing column curvature_per_m"), std::string::npos) << r.err;
}

TEST(TrajectoryCostCli, GradeIsAnOptionalColumnThatTheMapRefuses) {
  const std::string climb =
      "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m,grade_rad\nup,0,10,0,0,0.05\nup,1,10,0,0,0.05\n"
      "level,0,10,0,0,0\nlevel,1,10,0,0,0\n";
  const std::string level_only =
      "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\nlevel,0,10,0,0\nlevel,1,10,0,0\n";
  const std::vector<std::string> args = {"--vehicle", kVehicle, "--tire", kTire, "--preset", "fast", "-"};
  const ToolRun direct = run(args, climb), without = run(args, level_only);
  ASSERT_EQ(direct.rc, 0) << direct.err;
  const auto table = rows(direct.out), reference = rows(without.out);
  EXPECT_GT(cell(table, 1, "total_wear_kg"), cell(table, 2, "total_wear_kg"));  // climbing wears the driven tires
  EXPECT_EQ(table[2], reference[1]);  // a zero grade column is the flat road
  std::vector<std::string> map_args = args;
  map_args.insert(map_args.end() - 1, {"--map", "--threads", "1"});
  const ToolRun from_map = run(map_args, climb);
  EXPECT_EQ(from_map.rc, 1);
  const auto map_table = rows(from_map.out);
  EXPECT_EQ(map_table[1][1], "outside_map");
  EXPECT_NE(map_table[1].back().find("grade_rad = 0.05: the map is for a flat road"), std::string::npos);
  EXPECT_EQ(map_table[2][1], "ok");
}

TEST(TrajectoryCostCli, TakesTheTiresOfTheNodesWheelFileAndRefusesOtherThanFourWheels) {
  const std::string one = "trajectory_id,time_s,speed_mps,accel_mps2,curvature_per_m\na,0,10,0,0\na,1,10,0,0\n";
  ToolRun r = run({"--vehicle", kVehicle, "--wheels", kSrc + "/config/vehicle_wheels.yaml", "--preset", "fast", "-"}, one);
  EXPECT_EQ(r.rc, 0) << r.err;
  const ToolRun by_tire = run({"--vehicle", kVehicle, "--tire", kTire, "--preset", "fast", "-"}, one);
  EXPECT_EQ(r.out, by_tire.out);  // the wheel file mounts that tire on all four wheels
  r = run({"--vehicle", kVehicle, "--wheels", kSrc + "/test/ros/two_wheels.yaml", "-"}, one);
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.err.find("not a four-wheel car"), std::string::npos) << r.err;
}

TEST(TrajectoryCostCli, GeneratedCandidatesFromTheMapAreWithinThreePercentOfDirect) {
  const ToolRun generated = run({"--generate", "4", "--seed", "3"});
  ASSERT_EQ(generated.rc, 0) << generated.err;
  EXPECT_EQ(rows(generated.out).size(), 401u);  // header + 4 x 100 samples
  const ToolRun r = run({"--vehicle", kVehicle, "--tire", kTire, "--preset", "fast", "--compare", "--threads", "1", "-"},
                    generated.out);
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto table = rows(r.out);
  ASSERT_EQ(table.size(), 5u);
  for (std::size_t row = 1; row < table.size(); ++row) EXPECT_LE(std::fabs(cell(table, row, "map_relative_error")), 0.03);
}

}  // namespace
}  // namespace tread_wear
