// Evaluator CSV: parsing of good rows (units, signs, defaults), every kind of bad row, and the output layout.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tread_wear/io/conditions_csv.h"

namespace tread_wear {
namespace {

const std::string kHeader = "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n";

ConditionsTable read(const std::string& text) {
  std::istringstream in(text);
  return readConditions(in, "test.csv");
}

void expectError(const std::string& text, const std::vector<std::string>& fragments) {
  try {
    read(text);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const ConditionsError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("test.csv: ", 0), 0u) << msg;
    for (const std::string& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(ConditionsCsv, GoodRows) {
  const ConditionsTable t = read("# comment\n" + std::string("load_n,speed_mps,slip_angle_rad,slip_ratio,path_radius_m,"
                                                             "tread_temperature_c\n") +
                                 "75,2,-0.17,0,0.06,45\n"
                                 "\n"
                                 "300, 20 ,0.02,-0.05,,\n"
                                 "400,0,0,0,-50,\n");
  ASSERT_EQ(t.points.size(), 3u);
  EXPECT_EQ(t.points[0].load_n, 75.0);
  EXPECT_EQ(t.points[0].speed_mps, 2.0);
  EXPECT_EQ(t.points[0].slip_angle_rad, -0.17);
  EXPECT_DOUBLE_EQ(t.points[0].path_curvature_per_m, 1.0 / 0.06);
  EXPECT_EQ(t.points[0].tread_temperature_c, 45.0);
  EXPECT_EQ(t.points[1].path_curvature_per_m, 0.0) << "empty radius = straight";
  EXPECT_EQ(t.points[1].slip_ratio, -0.05);
  EXPECT_TRUE(std::isnan(t.points[1].tread_temperature_c)) << "empty temperature = unknown";
  EXPECT_EQ(t.points[2].speed_mps, 0.0) << "standstill is valid input (low-speed convention)";
  EXPECT_EQ(t.points[2].path_curvature_per_m, -1.0 / 50.0) << "negative radius = right turn";
  EXPECT_EQ(t.cells[1][1], "20") << "cells kept as given (trimmed)";
}

TEST(ConditionsCsv, BadInput) {
  expectError("", {"no header"});
  expectError(kHeader, {"no condition rows"});
  expectError("speed_mps,slip_angle_rad,slip_ratio,load_n\n2,0.1,0,75\n", {"missing column 'path_radius_m'"});
  expectError("speed_mps,slip_angle_deg,slip_ratio,path_radius_m,load_n\n", {"unknown column 'slip_angle_deg'"});
  expectError("speed_mps,speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n", {"'speed_mps' appears twice"});
  expectError(kHeader + "2,0.1,0,0,75\n2,0.1,0,0\n", {"row 2 (line 3)", "4 cells", "header has 5"});
  expectError(kHeader + "2,abc,0,0,75\n", {"row 1 (line 2)", "column 'slip_angle_rad' = 'abc'", "finite number"});
  expectError(kHeader + "2,0.1,0,0,NaN\n", {"row 1", "column 'load_n' = 'NaN'", "finite number"});
  expectError(kHeader + "2,0.1,0,0,inf\n", {"column 'load_n'", "finite number"});
  expectError(kHeader + "2,0.1,0,0,-75\n", {"column 'load_n' = '-75'", "> 0"});
  expectError(kHeader + "2,1.5708,0,0,75\n", {"column 'slip_angle_rad' = '1.5708'", "90 deg"});
  expectError(kHeader + "2,-10,0,0,75\n", {"column 'slip_angle_rad'", "radians"});
  expectError(kHeader + "-2,0.1,0,0,75\n", {"column 'speed_mps' = '-2'", ">= 0"});
  expectError(kHeader + "2,0.1,-1,0,75\n", {"column 'slip_ratio'", "> -1"});
  expectError(kHeader + "2,,0,0,75\n", {"column 'slip_angle_rad'", "required"});
  expectError(kHeader + "2,0.1,0,\"0,75\n", {"line 2", "unterminated quote"});
}

TEST(ConditionsCsv, OutputLayout) {
  const ConditionsTable t = read(kHeader + "2,0.1,0,,75\n");
  WearResult r;
  r.fx_n = 0.1;
  r.fy_n = -1.0 / 3.0;
  std::ostringstream out;
  writeEvaluations(out, t, {r});
  std::istringstream lines(out.str());
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  EXPECT_EQ(header,
            "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n,fx_n,fy_n,mz_nm,wear_rate_kg_per_m,"
            "wear_rate_kg_per_s,stick_fraction,slide_fraction,exact_stick_fraction");
  // Input cells as given, then results at round-trip precision (-1/3 needs 16-17 digits).
  EXPECT_EQ(row.rfind("2,0.1,0,,75,0.1,", 0), 0u) << row;
  const std::string fy = row.substr(std::string("2,0.1,0,,75,0.1,").size());
  EXPECT_EQ(std::stod(fy.substr(0, fy.find(','))), -1.0 / 3.0);
  EXPECT_THROW(writeEvaluations(out, t, {}), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
