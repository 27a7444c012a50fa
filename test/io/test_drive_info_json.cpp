// Drive metadata (io/drive_info_json.h): what tread_wear_drive writes, tread_wear_replay reads back unchanged, and
// metadata that cannot be used is refused with the key or phase at fault. Also the replay summary's documents
// (io/replay_summary_json.h), which carry the metadata on.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "tread_wear/io/drive_info_json.h"
#include "tread_wear/io/replay_summary_json.h"

namespace tread_wear {
namespace {

SpeedProfile shortProfile() {
  return SpeedProfile({0, 2, 6, 9, 12}, {0, 10 / 3.6, 40 / 3.6, 40 / 3.6, 20 / 3.6}, {{"A", 0, 6}, {"B", 6, 12.5}},
                      "short");
}

std::string shortDriveInfo() {
  const SpeedProfile profile = shortProfile();
  const RouteParams route_params;
  return driveInfoJson({profile.name(), profile.duration_s(), profile.totalDistance_m(), profile.phases(), {}},
                       buildRoute(profile, route_params), route_params, VehicleParams{},
                       {50.0, {"fl", "fr", "rl", "rr"}, 1000.25, 2.5});
}

/// The message of the DriveInfoError that parsing text throws; empty when it parses.
std::string parseError(const std::string& text) {
  try {
    parseDriveInfo(text);
  } catch (const DriveInfoError& e) {
    return e.what();
  }
  return "";
}

TEST(DriveInfoJson, BuildThenParseGivesBackPhasesAndOffset) {
  const std::string text = shortDriveInfo();
  const DriveMetadata m = parseDriveInfo(text);
  EXPECT_EQ(m.text, text);
  EXPECT_EQ(m.time_offset_s, 1000.25);
  ASSERT_EQ(m.phases.size(), 2u);
  EXPECT_EQ(m.phases[0].name, "A");
  EXPECT_EQ(m.phases[0].start_s, 0.0);
  EXPECT_EQ(m.phases[0].end_s, 6.0);
  EXPECT_EQ(m.phases[1].name, "B");
  EXPECT_EQ(m.phases[1].start_s, 6.0);
  EXPECT_EQ(m.phases[1].end_s, 12.5);
}

TEST(DriveInfoJson, DocumentTellsProfileVehicleAndRoute) {
  const nlohmann::json j = nlohmann::json::parse(shortDriveInfo());
  EXPECT_EQ(j.at("format"), "tread_wear_drive");
  EXPECT_EQ(j.at("version"), 1);
  EXPECT_EQ(j.at("profile"), "short");
  EXPECT_EQ(j.at("rate_hz"), 50.0);
  EXPECT_EQ(j.at("duration_s"), 12.0);
  EXPECT_EQ(j.at("wheels"), nlohmann::json({"fl", "fr", "rl", "rr"}));
  EXPECT_EQ(j.at("vehicle").at("name"), VehicleParams{}.name);
  EXPECT_EQ(j.at("vehicle").at("mass_kg"), VehicleParams{}.mass_kg);
  EXPECT_EQ(j.at("route").at("seed"), RouteParams{}.seed);
  EXPECT_EQ(j.at("route").at("max_abs_lateral_accel_mps2"), 2.5);
  EXPECT_TRUE(j.at("route").at("events").is_object());
}

TEST(DriveInfoJson, PhasesAndOffsetAreOptional) {
  const DriveMetadata m = parseDriveInfo(R"({"format": "tread_wear_drive"})");
  EXPECT_TRUE(m.phases.empty());
  EXPECT_EQ(m.time_offset_s, 0.0);
}

TEST(DriveInfoJson, MalformedMetadataNamesTheProblem) {
  EXPECT_NE(parseError("{\"phases\": [").find("not JSON"), std::string::npos);
  EXPECT_EQ(parseError("[1, 2]"), "not a JSON object but a array");
  EXPECT_EQ(parseError(R"({"time_offset_s": "1000"})"), "time_offset_s must be a number");
  EXPECT_EQ(parseError(R"({"phases": {"name": "A"}})"), "phases must be a list");
  EXPECT_EQ(parseError(R"({"phases": [7]})"), "phases[0] must be a map");
  EXPECT_EQ(parseError(R"({"phases": [{"name": "A", "start_s": 0, "end_s": 1}, {"start_s": 1, "end_s": 2}]})"),
            "phases[1].name must be a string");
  EXPECT_EQ(parseError(R"({"phases": [{"name": "A", "end_s": 1}]})"), "phases[0].start_s must be a number");
  EXPECT_EQ(parseError(R"({"phases": [{"name": "A", "start_s": 0, "end_s": null}]})"),
            "phases[0].end_s must be a number");
}

TEST(ReplaySummaryJson, CarriesTheRunAndTheDriveMetadata) {
  ReplaySummary summary;
  summary.complete = true;
  summary.end_s = 12.0;
  const std::string drive = shortDriveInfo();
  const nlohmann::json j =
      nlohmann::json::parse(replaySummaryDocument(summary, ReplaySettings{}, {"in.bag", 0.5, 1.5, drive}));
  EXPECT_EQ(j.at("format"), "tread_wear_replay_summary");
  EXPECT_EQ(j.at("complete"), true);
  EXPECT_EQ(j.at("input"), "in.bag");
  EXPECT_EQ(j.at("bag_read_s"), 0.5);
  EXPECT_EQ(j.at("compute_cpu_s"), 1.5);
  EXPECT_EQ(j.at("drive"), nlohmann::json::parse(drive));
  const nlohmann::json without =
      nlohmann::json::parse(replaySummaryDocument(summary, ReplaySettings{}, {"in.bag", 0.5, 1.5, ""}));
  EXPECT_FALSE(without.contains("drive"));
}

TEST(ReplaySummaryJson, IncompleteSummaryNamesReasonAndInput) {
  const std::string text = incompleteReplaySummary("in.bag", "replay did not finish");
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(nlohmann::json::parse(text), nlohmann::json({{"format", "tread_wear_replay_summary"},
                                                         {"version", 1},
                                                         {"complete", false},
                                                         {"incomplete_reason", "replay did not finish"},
                                                         {"input", "in.bag"}}));
}

}  // namespace
}  // namespace tread_wear
