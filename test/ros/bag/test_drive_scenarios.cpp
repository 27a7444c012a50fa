// tread_wear_drive's scenarios (docs/drive.md, "Scenarios"), run in-process: a manoeuvre's bag carries its steady
// inputs and its scenario metadata, the mass and drive-layout overrides reach the written loads and the metadata,
// and bad options are usage errors naming the option.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/cli/command_line.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/ros/bag/drive_cli.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;

struct CliRun {
  int exit_code;
  std::string out, err;
};

CliRun runDrive(std::vector<std::string> args) {
  args.insert(args.begin(), "tread_wear_drive");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int code = runDriveCli(static_cast<int>(argv.size()), argv.data(), kSource, out, err);
  return {code, out.str(), err.str()};
}

std::string tempPath(const std::string& name) { return ::testing::TempDir() + name; }

nlohmann::json driveInfo(const std::string& bag_path) {
  rosbag::Bag bag(bag_path);
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{kDriveInfoTopic}));
  for (const rosbag::MessageInstance& m : view) return nlohmann::json::parse(m.instantiate<std_msgs::String>()->data);
  return nlohmann::json();
}

/// The first load written for the wheel.
double firstLoad(const std::string& bag_path, int wheel) {
  rosbag::Bag bag(bag_path);
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{wheelInputTopics(wheelName(wheel)).load}));
  for (const rosbag::MessageInstance& m : view) return m.instantiate<WheelLoad>()->load_n;
  return -1.0;
}

TEST(DriveScenarios, CruiseBagCarriesItsScenarioAndTheOverriddenCar) {
  const std::string bag = tempPath("cruise.bag");
  const CliRun r = runDrive({"--manoeuvre", "cruise", "--speed-kmh", "90", "--duration-s", "4", "--rate-hz", "10",
                             "--mass-kg", "1800", "--drive-layout", "rear", "--out", bag});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json info = driveInfo(bag);
  const nlohmann::json& scenario = info.at("scenario");
  EXPECT_EQ(scenario.at("manoeuvre"), "cruise");
  EXPECT_NEAR(scenario.at("settings").at("speed_mps").get<double>(), 25.0, 1e-12);
  EXPECT_EQ(scenario.at("max_abs_accel_mps2").get<double>(), 0.0);
  EXPECT_EQ(scenario.at("max_abs_lateral_accel_mps2").get<double>(), 0.0);
  EXPECT_NEAR(scenario.at("distance_m").get<double>(), 100.0, 1e-9);
  EXPECT_EQ(scenario.at("duration_s").get<double>(), 4.0);
  EXPECT_EQ(info.at("vehicle").at("mass_kg").get<double>(), 1800.0);
  EXPECT_EQ(info.at("vehicle").at("drive_layout"), "rear");
  // The written loads are the heavier car's: static share of 1800 kg (CoG kept) plus the aero transfer at 25 m/s.
  VehicleParams car = loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml");
  car.mass_kg = 1800.0;
  car.drive_layout = DriveLayout::kRear;
  VehicleState expected;
  VehicleModel(car).evaluate({25.0, 0.0, 0.0}, &expected);
  for (int w = 0; w < kWheelCount; ++w) EXPECT_FLOAT_EQ(firstLoad(bag, w), expected.wheels[w].load_n) << wheelName(w);
}

// A style's drive of a profile carries the style, its envelope and the measured figures, inside the envelope.
TEST(DriveScenarios, StyleDriveRecordsItsEnvelopeAndStaysInside) {
  const std::string csv = tempPath("stop_and_go.csv");
  {
    std::ofstream f(csv);
    f << "# Phases: Go 0-25, Again 25-50\ntime_s,speed_kmh\n0,0\n3,0\n10,30\n20,30\n25,0\n30,0\n35,20\n45,40\n50,0\n"
         "53,0\n";
  }
  const std::string bag = tempPath("style.bag");
  const CliRun r =
      runDrive({"--profile", csv, "--style", "aggressive", "--max-accel-mps2", "2.5", "--rate-hz", "20", "--out", bag});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json scenario = driveInfo(bag).at("scenario");
  EXPECT_EQ(scenario.at("manoeuvre"), "profile");
  EXPECT_EQ(scenario.at("style"), "aggressive");
  EXPECT_EQ(scenario.at("settings").at("max_accel_mps2").get<double>(), 2.5);  // the option over the style
  EXPECT_EQ(scenario.at("settings").at("max_decel_mps2").get<double>(), 4.0);
  EXPECT_LE(scenario.at("max_abs_accel_mps2").get<double>(), 4.0 + 1e-9);
  EXPECT_GT(scenario.at("max_abs_accel_mps2").get<double>(), 2.0);
  EXPECT_GT(scenario.at("duration_s").get<double>(), 0.0);
  EXPECT_EQ(driveInfo(bag).at("phases").size(), 2u);
}

// A bad option is a usage error (exit 2) whose message names the option; no drive is written.
TEST(DriveScenarios, BadOptionsAreUsageErrorsNamingTheOption) {
  const std::string out = tempPath("never.bag");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--manoeuvre", "drift"}, "--manoeuvre must be profile, cruise, circle or accel, not 'drift'"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "-20", "--duration-s", "10"}, "--speed-kmh out of range"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "50", "--duration-s", "0"}, "--duration-s out of range"},
      {{"--manoeuvre", "cruise", "--duration-s", "10"}, "--manoeuvre cruise needs --speed-kmh"},
      {{"--manoeuvre", "circle", "--speed-kmh", "50", "--lateral-accel", "12", "--duration-s", "10"},
       "--lateral-accel out of range: lateral_accel_mps2 = 12: must be finite, > 0 and <= 8 (0.8 g)"},
      {{"--manoeuvre", "circle", "--speed-kmh", "50", "--lateral-accel", "3", "--duration-s", "10", "--direction",
        "up"},
       "--direction must be left or right, not 'up'"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "50", "--duration-s", "10", "--lateral-accel", "3"},
       "--lateral-accel is not an option of --manoeuvre cruise"},
      {{"--manoeuvre", "accel", "--low-speed-kmh", "80", "--high-speed-kmh", "30", "--accel-mps2", "2", "--decel-mps2",
        "3", "--duration-s", "10"},
       "--high-speed-kmh out of range"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "50", "--duration-s", "10", "--profile", "x.csv"},
       "--profile is not an option of --manoeuvre cruise"},
      {{"--style", "sporty"}, "--style must be calm, normal or aggressive, not 'sporty'"},
      {{"--style", "calm", "--max-lateral-accel-mps2", "9"},
       "--max-lateral-accel-mps2 out of range: max_lateral_accel_mps2 = 9: must be finite, > 0 and <= 8 (0.8 g)"},
      {{"--max-decel-mps2", "-2"}, "--max-decel-mps2 out of range"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "50", "--duration-s", "10", "--style", "calm"},
       "--style is not an option of --manoeuvre cruise"},
      {{"--mass-kg", "-5"}, "--mass-kg out of range: mass_kg = -5: must be finite and > 0"},
      {{"--drive-layout", "middle"}, "--drive-layout must be front, rear or all, not 'middle'"},
      {{"--manoeuvre", "cruise", "--speed-kmh", "50", "--duration-s", "10", "--laps", "2"},
       "--laps is an option of --programme only"},
      {{"--mirror"}, "--mirror is an option of --programme only"}};
  for (const auto& [options, message] : cases) {
    std::vector<std::string> args = options;
    args.push_back("--out");
    args.push_back(out);
    const CliRun r = runDrive(args);
    EXPECT_EQ(r.exit_code, kExitUsage) << message;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
}

// A LEON-T test section as a drive: its scenario, laps and distance (two laps of the urban loop, 2 x 518.4 m) and the
// Kuga's mass; bad programme options are usage errors naming the option; a missing programme is a data error.
TEST(DriveScenarios, ProgrammeSectionIsADriveOfItsLaps) {
  const std::string bag = tempPath("urban.bag");
  const std::string programme = kSource + "/data/leon_t_idiada";
  const CliRun r = runDrive(
      {"--programme", programme, "--section", "Urban_br_20kph", "--laps", "2", "--rate-hz", "10", "--out", bag});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json info = driveInfo(bag);
  const nlohmann::json& scenario = info.at("scenario");
  EXPECT_EQ(scenario.at("manoeuvre"), "programme");
  EXPECT_EQ(scenario.at("settings").at("laps").get<double>(), 2.0);
  EXPECT_NEAR(scenario.at("distance_m").get<double>(), 2.0 * 518.4, 0.1);
  EXPECT_EQ(info.at("vehicle").at("mass_kg").get<double>(), 1644.0);
  EXPECT_LE(scenario.at("max_abs_lateral_accel_mps2").get<double>(), 4.0 + 1e-6);

  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--programme", programme}, "--programme needs --section"},
      {{"--programme", programme, "--section", "Moon"}, "--section 'Moon' is not a test section of the programme"},
      {{"--programme", programme, "--section", "Rural_60_kph", "--laps", "0"}, "--laps must be >= 1"},
      {{"--programme", programme, "--section", "Rural_60_kph", "--corner-lateral-accel-mps2", "-1"},
       "--corner-lateral-accel-mps2 out of range"},
      {{"--programme", programme, "--section", "Rural_60_kph", "--style", "calm"},
       "--style is not an option of --programme"}};
  for (const auto& [options, message] : cases) {
    std::vector<std::string> args = options;
    args.push_back("--out");
    args.push_back(tempPath("never_programme.bag"));
    const CliRun bad = runDrive(args);
    EXPECT_EQ(bad.exit_code, 2) << message;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
  }
  const CliRun missing = runDrive({"--programme", "/nonexistent", "--section", "Run-in", "--out", tempPath("x.bag")});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("/nonexistent/turns.csv: cannot open"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace tread_wear
