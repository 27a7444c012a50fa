// The node's planner (ros/node_planner.h) without a master: availability and its reason, the wheel mapping (the
// node's wheels in any order give the same costs at the same vehicle places), mode direct equal to the core on the
// same setup, bad samples and malformed trajectories named in the reply, the map built off the caller's thread and
// equal to direct at its nodes, rebuilds on a preset change and on a tread temperature change beyond the step (only
// for tires that use temperature), and the latched message's layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "tread_wear/io/params_io.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/planning/wear_map.h"
#include "tread_wear/ros/node_planner.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;

using Wheels = std::vector<std::unique_ptr<WheelPipeline>>;

/// The car of config/vehicle_wheels.yaml at the fast preset; tire_override (if given) on every wheel.
Wheels carWheels(bool reversed, const TireParams* tire_override = nullptr) {
  NodeConfig c = loadNodeConfigFile(kSource + "/config/vehicle_wheels.yaml");
  c.model.preset = Preset::kFast;
  if (reversed) std::reverse(c.wheels.begin(), c.wheels.end());
  Wheels wheels;
  for (const WheelConfig& wc : c.wheels) {
    if (tire_override != nullptr)
      wheels.push_back(std::make_unique<WheelPipeline>(wc, *tire_override, c));
    else
      wheels.push_back(WheelPipeline::load(wc, c));
  }
  return wheels;
}

WearModelOptions fastModel() {
  WearModelOptions m;
  m.preset = Preset::kFast;
  return m;
}

NodePlannerConfig plannerConfig(bool build_map) {
  NodePlannerConfig p;
  p.vehicle_params = kSource + "/config/vehicle_passenger_car.yaml";
  p.build_map = build_map;
  p.map_speed_mps = {5.0, 10.0, 20.0};
  p.map_accel_x_mps2 = {-1.0, 0.0, 1.0};
  p.map_lateral_share = {-0.5, 0.0, 0.5};
  return p;
}

tread_wear::Trajectory trajectory(const std::string& id, const std::vector<TrajectorySample>& samples) {
  tread_wear::Trajectory t;
  t.id = id;
  for (const TrajectorySample& s : samples) {
    t.time_s.push_back(s.time_s);
    t.speed_mps.push_back(s.speed_mps);
    t.accel_mps2.push_back(s.accel_mps2);
    t.path_curvature_per_m.push_back(s.path_curvature_per_m);
  }
  return t;
}

const std::vector<TrajectorySample> kCurve = {{0.0, 12.0, 0.5, 0.01}, {0.5, 12.25, 0.5, 0.015}, {1.0, 12.5, 0.5, 0.02}};

/// Waits (without asserting any time) until the planner has built `version` maps; false after a generous minute.
bool waitForMap(const NodePlanner& planner, std::uint32_t version) {
  for (int i = 0; i < 6000 && planner.mapVersion() < version; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return planner.mapVersion() >= version;
}

TEST(NodePlanner, UnavailableWithTheReason) {
  NodeConfig two = loadNodeConfigFile(kSource + "/test/ros/two_wheels.yaml");
  Wheels wheels;
  for (WheelConfig wc : two.wheels) {
    wc.tire_params = kSource + "/config/tires/grosch_wheel.yaml";  // the rostests' file names it from its launch
    wheels.push_back(WheelPipeline::load(wc, two));
  }
  NodePlanner planner(plannerConfig(false), wheels, fastModel(), nullptr);
  EXPECT_FALSE(planner.available());
  EXPECT_NE(planner.reason().find("not a four-wheel car"), std::string::npos) << planner.reason();
  tread_wear::EvaluateTrajectories::Request req;
  tread_wear::EvaluateTrajectories::Response res;
  req.trajectories.push_back(trajectory("a", kCurve));
  planner.evaluate(req, Preset::kFast, 0.0, &res);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("planner unavailable: the wheels [a, b] are not a four-wheel car"), std::string::npos)
      << res.message;

  const Wheels car = carWheels(false);
  NodePlannerConfig no_vehicle = plannerConfig(false);
  no_vehicle.vehicle_params.clear();
  NodePlanner without(no_vehicle, car, fastModel(), nullptr);
  EXPECT_FALSE(without.available());
  EXPECT_NE(without.reason().find("planner/vehicle_params"), std::string::npos) << without.reason();
}

TEST(NodePlanner, DirectModeIsTheCoreCostAtTheVehiclePlacesWhateverTheWheelOrder) {
  const Wheels wheels = carWheels(false), reversed = carWheels(true);
  NodePlanner planner(plannerConfig(false), wheels, fastModel(), nullptr);
  NodePlanner planner_reversed(plannerConfig(false), reversed, fastModel(), nullptr);
  ASSERT_TRUE(planner.available()) << planner.reason();
  tread_wear::EvaluateTrajectories::Request req;
  req.mode = "direct";
  req.trajectories.push_back(trajectory("curve", kCurve));
  tread_wear::EvaluateTrajectories::Response res, res_reversed;
  planner.evaluate(req, Preset::kFast, 0.0, &res);
  planner_reversed.evaluate(req, Preset::kFast, 0.0, &res_reversed);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.costs.size(), 1u);
  EXPECT_EQ(res.costs[0].id, "curve");
  EXPECT_EQ(res.costs[0].status, tread_wear::TrajectoryWearCost::STATUS_OK);
  EXPECT_EQ(res.preset, "fast");
  for (int i = 0; i < kWheelCount; ++i) {
    EXPECT_EQ(res.wheels[static_cast<std::size_t>(i)], wheelName(i));
    EXPECT_EQ(res_reversed.wheels[static_cast<std::size_t>(i)], wheelName(i));
  }
  EXPECT_EQ(res.costs[0].wheel_wear_kg, res_reversed.costs[0].wheel_wear_kg);

  VehicleWearSetup setup;
  setup.vehicle = loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml");
  setup.tires.fill(loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml"));
  setup.model.preset = Preset::kFast;
  const TrajectoryCost core = TrajectoryCostEvaluator(setup).evaluate(kCurve.data(), kCurve.size());
  ASSERT_TRUE(core.ok());
  EXPECT_EQ(res.costs[0].total_wear_kg, core.total_wear_kg);
  EXPECT_EQ(res.costs[0].distance_m, core.distance_m);
  for (std::size_t i = 0; i < kWheelCount; ++i) EXPECT_EQ(res.costs[0].stick_fraction[i], core.stick_fraction[i]);
}

TEST(NodePlanner, BadSamplesAndMalformedRequestsAreNamed) {
  const Wheels wheels = carWheels(false);
  NodePlanner planner(plannerConfig(false), wheels, fastModel(), nullptr);
  tread_wear::EvaluateTrajectories::Request req;
  req.mode = "direct";
  std::vector<TrajectorySample> bad = kCurve;
  bad[2].speed_mps = std::numeric_limits<double>::quiet_NaN();
  req.trajectories.push_back(trajectory("nan", bad));
  tread_wear::Trajectory ragged = trajectory("ragged", kCurve);
  ragged.accel_mps2.pop_back();
  req.trajectories.push_back(ragged);
  tread_wear::Trajectory ragged_grade = trajectory("ragged_grade", kCurve);
  ragged_grade.grade_rad = {0.01};  // optional, but then one per sample
  req.trajectories.push_back(ragged_grade);
  req.trajectories.push_back(trajectory("empty", {}));
  req.trajectories.push_back(trajectory("good", kCurve));
  tread_wear::EvaluateTrajectories::Response res;
  planner.evaluate(req, Preset::kFast, 0.0, &res);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.costs.size(), 5u);
  EXPECT_EQ(res.costs[0].status, tread_wear::TrajectoryWearCost::STATUS_BAD_INPUT);
  EXPECT_NE(res.costs[0].message.find("sample 2: speed_mps = nan: must be finite"), std::string::npos);
  EXPECT_EQ(res.costs[1].status, tread_wear::TrajectoryWearCost::STATUS_BAD_INPUT);
  EXPECT_NE(res.costs[1].message.find("arrays of unequal length"), std::string::npos) << res.costs[1].message;
  EXPECT_NE(res.costs[2].message.find("grade_rad 1 (0 = flat road)"), std::string::npos) << res.costs[2].message;
  EXPECT_NE(res.costs[3].message.find("empty trajectory"), std::string::npos);
  EXPECT_EQ(res.costs[4].status, tread_wear::TrajectoryWearCost::STATUS_OK);

  req.mode = "fastest";
  planner.evaluate(req, Preset::kFast, 0.0, &res);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("unknown mode 'fastest'"), std::string::npos);
  req.mode = "map";  // the map is off in this configuration
  planner.evaluate(req, Preset::kFast, 0.0, &res);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("use mode direct"), std::string::npos) << res.message;
}

TEST(NodePlanner, BuildsTheMapOffTheCallersThreadAndRebuildsOnAPresetChange) {
  const Wheels wheels = carWheels(false);
  std::atomic<int> published{0};
  std::atomic<bool> on_caller_thread{false};
  const std::thread::id caller = std::this_thread::get_id();
  tread_wear::PlannerWearMap last_message;
  std::mutex message_mutex;
  NodePlanner planner(plannerConfig(true), wheels, fastModel(),
                      [&](tread_wear::PlannerWearMap& message) {
                        if (std::this_thread::get_id() == caller) on_caller_thread = true;
                        const std::lock_guard<std::mutex> lock(message_mutex);
                        last_message = message;
                        ++published;
                      });
  ASSERT_TRUE(planner.refresh(Preset::kFast, 0.0));
  EXPECT_FALSE(planner.refresh(Preset::kFast, 0.1));  // nothing changed
  ASSERT_TRUE(waitForMap(planner, 1)) << planner.buildError();
  EXPECT_FALSE(on_caller_thread);
  const auto map = planner.map();
  ASSERT_TRUE(map);
  EXPECT_EQ(map->setup().model.preset, Preset::kFast);

  // Straight at 10 m/s without acceleration is a node (lateral share 0): the map equals direct there.
  const std::vector<TrajectorySample> at_node = {{0.0, 10.0, 0.0, 0.0}, {2.0, 10.0, 0.0, 0.0}};
  tread_wear::EvaluateTrajectories::Request req;
  req.trajectories.push_back(trajectory("node", at_node));
  tread_wear::EvaluateTrajectories::Response from_map, direct;
  planner.evaluate(req, Preset::kFast, 0.0, &from_map);
  req.mode = "direct";
  planner.evaluate(req, Preset::kFast, 0.0, &direct);
  ASSERT_TRUE(from_map.success && direct.success) << from_map.message << direct.message;
  EXPECT_EQ(from_map.mode, "map");
  EXPECT_EQ(from_map.map_fingerprint, fingerprintText(map->fingerprint()));
  EXPECT_NEAR(from_map.costs[0].total_wear_kg, direct.costs[0].total_wear_kg, direct.costs[0].total_wear_kg * 1e-12);

  {
    const std::lock_guard<std::mutex> lock(message_mutex);
    const std::size_t nodes = map->nodeCount();
    EXPECT_EQ(nodes, 27u);
    EXPECT_EQ(last_message.fingerprint, fingerprintText(map->fingerprint()));
    EXPECT_EQ(last_message.speed_mps, map->params().speed_mps);
    EXPECT_EQ(last_message.lateral_share, map->params().lateral_share);
    ASSERT_EQ(last_message.wear_rate_kg_per_s.size(), 4 * nodes);
    EXPECT_EQ(last_message.wear_rate_kg_per_s[2 * nodes + 13], map->nodeWearRate_kg_per_s(2, 13));  // wheel-major
    EXPECT_EQ(last_message.stick_fraction[3 * nodes + 5], map->nodeStickFraction(3, 5));
    EXPECT_EQ(last_message.preset, "fast");
    EXPECT_EQ(last_message.version, 1u);
    EXPECT_EQ(last_message.wheels[1], "front_right");
  }

  ASSERT_TRUE(planner.refresh(Preset::kStandard, 1.0));  // dynamic_reconfigure changed the preset
  ASSERT_TRUE(waitForMap(planner, 2)) << planner.buildError();
  EXPECT_EQ(planner.map()->setup().model.preset, Preset::kStandard);
  EXPECT_NE(planner.map()->fingerprint(), map->fingerprint());
  EXPECT_EQ(published.load(), 2);
  planner.stop();
}

TEST(NodePlanner, RebuildsOnTreadTemperatureOnlyForTiresThatUseIt) {
  TireParams warm_tire = loadTireParams(kSource + "/config/tires/passenger_205_55_r16.yaml");
  const Wheels plain = carWheels(false);
  NodePlannerConfig config = plannerConfig(true);
  config.map_speed_mps = {10.0};  // a one-node map: this test is about when it is rebuilt
  config.map_accel_x_mps2 = {0.0};
  config.map_lateral_share = {0.0};
  {
    NodePlanner planner(config, plain, fastModel(), nullptr);
    ASSERT_TRUE(planner.refresh(Preset::kFast, 0.0));
    for (auto& w : plain) w->setTemperature(0.5, 60.0);
    EXPECT_FALSE(planner.refresh(Preset::kFast, 0.5));  // temperature_enabled false: the tire ignores it
  }
  warm_tire.wear.temperature_enabled = true;
  const Wheels warm = carWheels(false, &warm_tire);
  NodePlanner planner(config, warm, fastModel(), nullptr);
  ASSERT_TRUE(planner.refresh(Preset::kFast, 0.0));
  warm[0]->setTemperature(1.0, 40.0);
  EXPECT_TRUE(planner.refresh(Preset::kFast, 1.0));   // unknown -> 40 degC
  warm[0]->setTemperature(2.0, 43.0);
  EXPECT_FALSE(planner.refresh(Preset::kFast, 2.0));  // within the 5 K step
  warm[0]->setTemperature(3.0, 46.0);
  EXPECT_TRUE(planner.refresh(Preset::kFast, 3.0));   // 6 K from the map's 40 degC
  EXPECT_TRUE(planner.refresh(Preset::kFast, 10.0));  // the reading went stale: unknown again
  ASSERT_TRUE(waitForMap(planner, 1)) << planner.buildError();
}

}  // namespace
}  // namespace tread_wear
