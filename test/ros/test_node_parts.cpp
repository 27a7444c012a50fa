// The node's parts, each alone and without a ROS master: configuration (io/wheel_config.h and the parameter-server
// side), the per-wheel pipeline, the services, persistence, reconfigure, diagnostics, markers, the realtime
// publisher and --help. Expected values come from the core library evaluated directly, never from the part itself.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "common/temp_file.h"
#include "common/allocation_counter.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/wheel_config.h"
#include "tread_wear/model/units.h"
#include "tread_wear/ros/node_config.h"
#include "tread_wear/ros/node_diagnostics.h"
#include "tread_wear/ros/node_help.h"
#include "tread_wear/pipeline/node_persistence.h"
#include "tread_wear/ros/node_reconfigure.h"
#include "tread_wear/ros/node_services.h"
#include "tread_wear/ros/realtime_publisher.h"
#include "tread_wear/ros/wear_markers.h"
#include "tread_wear/ros/wheel_pipeline.h"


namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kTireFile = kSource + "/config/tires/grosch_wheel.yaml";

// The rig point of paper Table 3 (75 N, alpha = -2 deg, R_t = 60 mm) at 0.5 m/s.
constexpr double kLoad = 75.0, kSpeed = 0.5, kCurvature = 1.0 / 0.060;
const double kSlipAngle = -2.0 * units::kDegree;

/// The node configuration of the rostests (test/ros/two_wheels.yaml) with tire paths from the source tree.
NodeConfig twoWheels() {
  NodeConfig c = loadNodeConfigFile(kSource + "/test/ros/two_wheels.yaml");
  for (WheelConfig& w : c.wheels) w.tire_params = kTireFile;
  return c;
}

/// Feeds the rig point to a wheel at time t_s [s]; temperature_c is sent when finite.
WheelPipeline::StepSettings stepSettings(Preset preset, double budget_s) {
  WheelPipeline::StepSettings settings;
  settings.preset = preset;
  settings.budget_s = budget_s;
  return settings;
}

void feed(WheelPipeline* w, double t_s, double temperature_c = std::numeric_limits<double>::quiet_NaN()) {
  w->setLoad(t_s, kLoad);
  w->setSlip(t_s, kSlipAngle, 0.0, kCurvature);
  w->setSpeed(t_s, kSpeed);
  if (std::isfinite(temperature_c)) w->setTemperature(t_s, temperature_c);
}

tread_wear::WheelState rigState() {
  tread_wear::WheelState s;
  s.load_n = kLoad;
  s.speed_mps = kSpeed;
  s.slip_angle_rad = kSlipAngle;
  s.path_curvature_per_m = kCurvature;
  s.tread_temperature_c = std::numeric_limits<double>::quiet_NaN();
  return s;
}

// ---------------------------------------------------------------------------------------------------------
// Configuration: one reader, one defaults table, one validation for the node and the replay.

/// A minimal document as the parameter server holds it: one wheel, every other key absent.
XmlRpc::XmlRpcValue minimalDocument() {
  XmlRpc::XmlRpcValue ns;
  ns["wheels"][0]["name"] = "a";
  ns["wheels"][0]["tire_params"] = "tires/grosch_wheel.yaml";
  return ns;
}

std::string readError(XmlRpc::XmlRpcValue document) {
  NodeConfig c;
  std::string error;
  EXPECT_FALSE(readNodeConfig(parameterTree(document), "", &c, &error)) << document.toXml();
  return error;
}

TEST(NodeConfig, AbsentKeysTakeTheDefaultsOfTheTable) {
  NodeConfig c;
  std::string error;
  XmlRpc::XmlRpcValue doc = minimalDocument();
  ASSERT_TRUE(readNodeConfig(parameterTree(doc), "/cfg", &c, &error)) << error;
  NodeConfig expected;  // the table's defaults
  WheelConfig w;
  w.name = "a";
  w.frame_id = "a";
  w.tire_params = "/cfg/tires/grosch_wheel.yaml";
  w.load_topic = "wheels/a/load";
  w.slip_topic = "wheels/a/slip";
  w.speed_topic = "wheels/a/speed";
  w.temperature_topic = "wheels/a/tread_temperature";
  w.wear_topic = "wheels/a/wear";
  expected.wheels = {w};
  expected.config_dir = "/cfg";
  EXPECT_EQ(c.describe(), expected.describe());
  EXPECT_EQ(c.wheels[0].tire_id, "unknown");
  EXPECT_FALSE(c.wheels[0].has_position);
}

TEST(NodeConfig, TheShippedFileReadsWithEveryKey) {
  const NodeConfig c = loadNodeConfigFile(kSource + "/config/vehicle_wheels.yaml");
  ASSERT_EQ(c.wheels.size(), 4u);
  EXPECT_EQ(c.wheels[0].name, "front_left");
  EXPECT_EQ(c.wheels[0].frame_id, "wheel_front_left");
  EXPECT_EQ(c.wheels[0].tire_id, "fl-0001");
  EXPECT_EQ(c.wheels[0].tire_params, kSource + "/config/tires/passenger_205_55_r16.yaml");
  EXPECT_TRUE(c.wheels[3].has_position);
  EXPECT_DOUBLE_EQ(c.wheels[3].position_m[1], -0.78);
  EXPECT_EQ(c.wheels[1].wear_topic, "wheels/front_right/wear");
  // The file states the defaults: it reads as the table.
  NodeConfig defaults;
  defaults.wheels = c.wheels;
  defaults.config_dir = c.config_dir;
  EXPECT_EQ(c.describe(), defaults.describe());
}

TEST(NodeConfig, TheParameterServerTreeReadsAsTheFile) {
  // test/ros/two_wheels.yaml as rosparam puts it on the parameter server (with the launch file's config_dir).
  XmlRpc::XmlRpcValue ns;
  ns["update_rate_hz"] = 50.0;
  ns["preset"] = "fast";
  ns["stale_timeout_s"] = 0.3;
  ns["max_step_s"] = 0.6;
  ns["marker_rate_hz"] = 2.0;
  ns["save_interval_s"] = 0.5;
  ns["config_dir"] = kSource + "/config";
  for (int i = 0; i < 2; ++i) {
    const std::string name = i == 0 ? "a" : "b";
    ns["wheels"][i]["name"] = name;
    ns["wheels"][i]["frame_id"] = "wheel_" + name;
    ns["wheels"][i]["tire_params"] = "tires/grosch_wheel.yaml";
    ns["wheels"][i]["tire_id"] = "tire-" + name;
  }
  NodeConfig from_server;
  std::string error;
  ASSERT_TRUE(readNodeConfig(parameterTree(ns), "", &from_server, &error)) << error;
  const std::string file = kSource + "/test/ros/two_wheels.yaml";
  TempFile with_dir("config_dir: " + kSource + "/config\n" + [&] {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }(), ".yaml");
  EXPECT_EQ(from_server.describe(), loadNodeConfigFile(with_dir.path()).describe());
  EXPECT_EQ(from_server.wheels[1].tire_params, kTireFile);
}

TEST(NodeConfig, IntegersAndNestedLimitsAreRead) {
  XmlRpc::XmlRpcValue ns;
  ns["update_rate_hz"] = 20;  // an int on the parameter server (YAML `20`)
  ns["limits"]["max_load_n"] = 5000;
  ns["wheels"][0]["name"] = "a";
  ns["wheels"][0]["tire_params"] = kTireFile;
  ns["wheels"][0]["position_m"][0] = 1;
  ns["wheels"][0]["position_m"][1] = -0.5;
  ns["wheels"][0]["position_m"][2] = 0.0;
  NodeConfig c;
  std::string error;
  ASSERT_TRUE(readNodeConfig(parameterTree(ns), "", &c, &error)) << error;
  EXPECT_EQ(c.update_rate_hz, 20.0);
  EXPECT_EQ(c.estimator.limits.max_load_n, 5000.0);
  EXPECT_EQ(c.estimator.limits.max_speed_mps, InputLimits().max_speed_mps);
  EXPECT_TRUE(c.wheels[0].has_position);
  EXPECT_EQ(c.wheels[0].position_m[1], -0.5);
}

TEST(NodeConfig, EachBadValueIsNamedWithItsConstraint) {
  XmlRpc::XmlRpcValue pair;
  pair[0] = 1;
  pair[1] = 2;
  XmlRpc::XmlRpcValue empty;
  empty.setSize(0);
  struct Case {
    const char* key;
    XmlRpc::XmlRpcValue value;
    const char* message;
  };
  const Case cases[] = {
      {"update_rate_hz", 0, "update_rate_hz = 0: must be in (0, 1000]"},
      {"update_rate_hz", 5000, "update_rate_hz = 5000: must be in (0, 1000]"},
      {"update_rate_hz", "fast", "update_rate_hz = \"fast\": must be a number [Hz]"},
      {"update_rate_hz", true, "update_rate_hz = true: must be a number [Hz]"},
      {"update_rate_hz", 1.0, "update_rate_hz = 1: must be >= 2 / max_step_s = 2 Hz"},
      {"marker_rate_hz", 200, "marker_rate_hz = 200: must be in [0, update_rate_hz = 100]"},
      {"budget_us", -1, "budget_us = -1: must be finite and >= 0"},
      {"min_speed_mps", 0, "min_speed_mps = 0: must be finite and > 0"},
      {"max_step_s", 0.1, "max_step_s = 0.1: must be finite and > stale_timeout_s"},
      {"limits", pair, "limits = [1, 2]: must be a map"},
      {"save_interval_s", 0, "save_interval_s = 0: must be finite and > 0"},
      {"preset", "turbo", "preset = \"turbo\": must be fast, standard, fine or reference"},
      {"turn_slip_orientation", "sideways", "turn_slip_orientation = \"sideways\": must be literal or flipped"},
      {"base_frame", "", "base_frame = '': must be non-empty"},
      {"state_file", 3, "state_file = 3: must be a string"},
      {"wheels", empty, "wheels = []: must be a non-empty list"},
      {"wheels", "a", "wheels = \"a\": must be a list of wheels"},
  };
  for (const Case& c : cases) {
    XmlRpc::XmlRpcValue doc = minimalDocument();
    doc[c.key] = c.value;
    EXPECT_EQ(readError(doc).rfind(c.message, 0), 0u) << c.key << ": " << readError(doc);
  }
  XmlRpc::XmlRpcValue limit = minimalDocument();
  limit["limits"]["max_load_n"] = -1;
  EXPECT_EQ(readError(limit).rfind("limits/max_load_n = -1: must be finite and > 0", 0), 0u) << readError(limit);
  XmlRpc::XmlRpcValue missing;
  missing["update_rate_hz"] = 50.0;
  EXPECT_EQ(readError(missing), "wheels = (missing): must be a list of wheels");
  XmlRpc::XmlRpcValue twice = minimalDocument();
  const XmlRpc::XmlRpcValue first = twice["wheels"][0];  // a copy: growing the list moves its elements
  twice["wheels"][1] = first;
  EXPECT_EQ(readError(twice), "wheels[].name = a: must be unique");
  XmlRpc::XmlRpcValue long_id = minimalDocument();
  long_id["wheels"][0]["tire_id"] = std::string(64, 'x');
  EXPECT_NE(readError(long_id).find("wheels[a].tire_id"), std::string::npos);
  XmlRpc::XmlRpcValue no_tire;
  no_tire["wheels"][0]["name"] = "a";
  EXPECT_EQ(readError(no_tire), "wheels[0].tire_params = (missing): must be given");
  XmlRpc::XmlRpcValue position = minimalDocument();
  position["wheels"][0]["position_m"] = pair;
  EXPECT_EQ(readError(position).rfind("wheels[0].position_m = [1, 2]: must be a list of three numbers", 0), 0u);
}

TEST(NodeConfig, AFileErrorNamesTheFile) {
  TempFile bad("update_rate_hz: 0.5\nwheels: [{name: a, tire_params: x.yaml}]\n", ".yaml");
  try {
    loadNodeConfigFile(bad.path());
    FAIL() << "accepted update_rate_hz 0.5 with max_step_s 1";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad.path() + ": update_rate_hz = 0.5: must be >= 2 / max_step_s", 0), 0u)
        << e.what();
  }
  EXPECT_THROW(loadNodeConfigFile(kSource + "/no/such/file.yaml"), std::runtime_error);
}

// The node at 1 Hz with max_step_s 1 integrated about half the wear: each timer period a little over 1 s was a
// clock jump. The slowest rate the validation accepts (2 / max_step_s) integrates a step a whole period late.
TEST(NodeConfig, TheSlowestAcceptedRateIntegratesALateStep) {
  NodeConfig c = twoWheels();
  c.estimator.max_step_s = 1.0;
  c.marker_rate_hz = 0.0;
  c.update_rate_hz = 2.0 / c.estimator.max_step_s;
  std::string error;
  ASSERT_TRUE(c.validate(&error)) << error;
  WheelPipeline w(c.wheels[0], loadTireParams(kTireFile), c);
  const double period = 1.0 / c.update_rate_hz;
  double t = 0.0;
  for (int k = 0; k < 10; ++k) {
    t += k == 5 ? 2.0 * period - 1e-3 : period * 1.001;  // timer jitter, and one step almost a period late
    feed(&w, t);
    w.step(t, stepSettings(Preset::kFast, 0.0));
  }
  EXPECT_EQ(w.snapshot().forward_jumps, 0u);
  EXPECT_EQ(w.snapshot().unaccounted_time_s, 0.0) << "every interval after the first step is integrated";
}

// ---------------------------------------------------------------------------------------------------------
// Per-wheel pipeline.

TEST(WheelPipeline, InInputTimeReceiveStepsOnTheInputsStampsWhateverTheirOrder) {
  const NodeConfig c = twoWheels();  // stale_timeout_s 0.3 s, max_step_s 0.6 s
  WheelPipeline w(c.wheels[0], loadTireParams(kTireFile), c);
  w.setInputTime(true);
  WheelPipeline::StepSettings settings = stepSettings(Preset::kFast, 0.0);
  settings.period_s = 0.5;
  // Inputs stamped 10.0 to 12.0 s every 20 ms; the speed arrives 10 samples (0.2 s) after the others, all within a
  // few milliseconds of wall time: the wheel steps at 10.0, 10.5, ..., 12.0 s of the stamps once the speed is there.
  auto sample = [](InputKind kind, int k, double v0, double v1 = 0.0, double v2 = 0.0) {
    InputSample s;
    s.t_s = 0.02 * k;
    s.kind = kind;
    s.value[0] = v0;
    s.value[1] = v1;
    s.value[2] = v2;
    return s;
  };
  double wall_s = 0.0;
  for (int k = 500; k <= 610; ++k) {
    if (k <= 600) {
      w.receive(sample(InputKind::kLoad, k, kLoad), wall_s += 1e-4, settings);
      w.receive(sample(InputKind::kSlip, k, kSlipAngle, 0.0, kCurvature), wall_s += 1e-4, settings);
    }
    if (k >= 510) w.receive(sample(InputKind::kSpeed, k - 10, kSpeed), wall_s += 1e-4, settings);
    if (k == 550) {
      EXPECT_LE(w.snapshot().step_time_s, 0.02 * 540 + 1e-9) << "a step waits for the speed";
    }
  }
  const WheelSnapshot s = w.snapshot();
  EXPECT_NEAR(s.step_time_s, 12.0, 1e-9);
  EXPECT_EQ(s.evaluations, 5u);
  EXPECT_EQ(s.stale_steps, 0u);
  EXPECT_EQ(s.forward_jumps, 0u);
  EXPECT_EQ(s.steps_past_lagging_input, 0u);
  EXPECT_NEAR(s.integrated_time_s, 2.0, 1e-9);
  EXPECT_EQ(s.unaccounted_time_s, 0.0) << "the grid starts at the first sample: no start-up loss";
  // A sample that is rejected is reported to the caller and counted, in input time as live.
  EXPECT_EQ(w.receive(sample(InputKind::kLoad, 601, -5.0), wall_s, settings), InputFault::kNegativeLoad);
  EXPECT_EQ(w.snapshot().inputs.sample(InputKind::kLoad).rejected, 1u);
}

TEST(WheelPipeline, TheOperatingPointKeepsAFreshTreadTemperature) {
  const NodeConfig c = twoWheels();
  WheelInputs in(c.estimator.limits);
  in.setLoad(10.0, kLoad);
  in.setSlip(10.0, kSlipAngle, 0.01, kCurvature);
  in.setSpeed(10.0, kSpeed);
  in.setTemperature(10.0, 80.0);
  const OperatingPoint fresh = operatingPoint(in, 10.1, c.estimator.stale_timeout_s);
  EXPECT_EQ(fresh.load_n, kLoad);
  EXPECT_EQ(fresh.slip_ratio, 0.01);
  EXPECT_EQ(fresh.path_curvature_per_m, kCurvature);
  EXPECT_EQ(fresh.tread_temperature_c, 80.0);
  EXPECT_TRUE(std::isnan(operatingPoint(in, 10.0 + 2 * c.estimator.stale_timeout_s, c.estimator.stale_timeout_s)
                             .tread_temperature_c));
}

/// A Grosch wheel whose wear law uses the tread temperature (Eq 25), so that dropping it changes the result.
TireParams temperatureTire() {
  TireParams tire = loadTireParams(kTireFile);
  tire.wear.temperature_enabled = true;
  return tire;
}

// The markers and the service evaluate what the loop evaluated: the same point, temperature included.
TEST(WheelPipeline, EvaluateInputsIsTheLoopsEvaluation) {
  const NodeConfig c = twoWheels();
  WheelPipeline w(c.wheels[0], temperatureTire(), c);
  feed(&w, 1.0, 120.0);
  w.step(1.0, stepSettings(Preset::kFast, 0.0));
  feed(&w, 1.02, 120.0);
  const WheelOutput& out = w.step(1.02, stepSettings(Preset::kFast, 0.0));
  ASSERT_TRUE(out.evaluated);
  const WheelSnapshot s = w.snapshot();
  WearModelOptions options = c.model;
  options.preset = Preset::kFast;
  const WearModel model(temperatureTire(), options);
  WearResult again;
  ASSERT_EQ(evaluateInputs(model, s.step_inputs, s.step_time_s, c.estimator.stale_timeout_s, &again), EvalStatus::kOk);
  EXPECT_EQ(again.wear_rate_kg_per_m, out.result.wear_rate_kg_per_m);
  EXPECT_EQ(again.fy_n, out.result.fy_n);
  OperatingPoint cold = operatingPoint(s.step_inputs, s.step_time_s, c.estimator.stale_timeout_s);
  cold.tread_temperature_c = std::numeric_limits<double>::quiet_NaN();
  WearResult without;
  model.evaluate(cold, &without);
  EXPECT_GT(std::fabs(without.wear_rate_kg_per_m / out.result.wear_rate_kg_per_m - 1.0), 0.01)
      << "the temperature must matter for this check to mean anything";
}

TEST(WheelPipeline, AZeroLoadWearsNothing) {
  const NodeConfig c = twoWheels();
  WearModelOptions options = c.model;
  const WearModel model(loadTireParams(kTireFile), options);
  WheelInputs in(c.estimator.limits);
  in.setLoad(0.0, 0.0);
  in.setSlip(0.0, kSlipAngle, 0.0, kCurvature);
  in.setSpeed(0.0, kSpeed);
  WearResult r;
  r.fy_n = 5.0;
  PatchFields fields;
  fields.resize(3, 2);
  EXPECT_EQ(evaluateInputs(model, in, 0.0, 1.0, &r, &fields), EvalStatus::kOk);
  EXPECT_EQ(r.fy_n, 0.0);
  EXPECT_EQ(r.wear_rate_kg_per_m, 0.0);
  EXPECT_EQ(r.stick_fraction, 1.0);
  EXPECT_EQ(fields.n_x_nodes, 0);
}

TEST(WheelPipeline, TheLoopStepAndMessageAllocateNothing) {
  const NodeConfig c = twoWheels();
  WheelPipeline w(c.wheels[0], loadTireParams(kTireFile), c);
  tread_wear::WheelWear msg;
  reserveStrings(&msg);
  feed(&w, 1.0);
  w.step(1.0, stepSettings(Preset::kFast, 0.0));
  fillMessage(w, ros::Time(1.0), Preset::kFast, &msg);  // the first message sets the wheel's names
  const long before = t_allocations;
  for (int k = 1; k <= 20; ++k) {
    const double t = 1.0 + 0.02 * k;
    feed(&w, t);
    w.step(t, stepSettings(k < 10 ? Preset::kFast : Preset::kStandard, k % 2 ? 0.0 : 1e-3));
    fillMessage(w, ros::Time(t), Preset::kStandard, &msg);
  }
  EXPECT_EQ(t_allocations - before, 0);
  EXPECT_EQ(msg.status, tread_wear::WheelWear::STATUS_OK);
  EXPECT_EQ(msg.wheel, "a");
  EXPECT_EQ(msg.tire_id, "tire-a");
  EXPECT_GT(msg.accumulated_loss_kg, 0.0);
}

TEST(WheelPipeline, ATireChangeAndARestoreAreWhatTheRecordSays) {
  const NodeConfig c = twoWheels();
  WheelPipeline w(c.wheels[0], loadTireParams(kTireFile), c);
  w.restore({"a", "restored-tire", 2e-6, 30.0, 1234.0});
  EXPECT_EQ(w.record().tire_id, "restored-tire");
  EXPECT_EQ(w.record().accumulated_loss_kg, 2e-6);
  std::string old;
  const WheelAccumulators a = w.changeTire("new-tire", 5678.0, &old);
  EXPECT_EQ(old, "restored-tire");
  EXPECT_EQ(a.distance_m, 30.0);
  const WheelRecord r = w.record();
  EXPECT_EQ(r.tire_id, "new-tire");
  EXPECT_EQ(r.accumulated_loss_kg, 0.0);
  EXPECT_EQ(r.reset_unix_s, 5678.0);
}

// ---------------------------------------------------------------------------------------------------------
// Services.

std::vector<std::unique_ptr<WheelPipeline>> pipelines(const NodeConfig& c) {
  std::vector<std::unique_ptr<WheelPipeline>> wheels;
  for (const WheelConfig& wc : c.wheels) wheels.push_back(WheelPipeline::load(wc, c));
  return wheels;
}

TEST(EvaluateWear, AppliesTheLiveInputLimits) {
  const NodeConfig c = twoWheels();
  const auto wheels = pipelines(c);
  tread_wear::EvaluateWear::Request req;
  tread_wear::EvaluateWear::Response res;
  req.wheel = "a";
  struct Case {
    double tread_wear::WheelState::*field;
    double value;
    const char* error;
  };
  // Each was evaluated before (the live topics reject them all).
  const Case cases[] = {
      {&tread_wear::WheelState::path_curvature_per_m, 500.0,
       "path_curvature_per_m = 500: must be within +-limits/max_abs_path_curvature_per_m = 100 [1/m]"},
      {&tread_wear::WheelState::load_n, 200e3, "load_n = 200000: must be <= limits/max_load_n = 100000 [N]"},
      {&tread_wear::WheelState::speed_mps, 150.0, "speed_mps = 150: must be <= limits/max_speed_mps = 100 [m/s]"},
      {&tread_wear::WheelState::slip_ratio, 1.5,
       "slip_ratio = 1.5: must be within +-limits/max_abs_slip_ratio = 1 and > -1 [-]"},
      {&tread_wear::WheelState::slip_angle_rad, 1.2,
       "slip_angle_rad = 1.2: must be within +-limits/max_abs_slip_angle_rad = 1 [rad]"},
      {&tread_wear::WheelState::load_n, std::numeric_limits<double>::quiet_NaN(), "load_n = nan: must be finite"},
      {&tread_wear::WheelState::load_n, -std::numeric_limits<double>::quiet_NaN(), "load_n = nan: must be finite"},
      {&tread_wear::WheelState::load_n, -1.0, "load_n = -1: must be >= 0 [N] (0 = wheel off the ground)"},
      {&tread_wear::WheelState::speed_mps, -1.0, "speed_mps = -1: must be >= 0 [m/s]"},
      {&tread_wear::WheelState::tread_temperature_c, 300.0,
       "tread_temperature_c = 300: must be in [limits/min_temperature_c, limits/max_temperature_c] = [-60, 250] "
       "[degC], or NaN for unknown"},
      {&tread_wear::WheelState::slip_ratio, std::numeric_limits<double>::infinity(), "slip_ratio = inf: must be finite"},
  };
  for (const Case& k : cases) {
    tread_wear::WheelState s = rigState();
    s.*k.field = k.value;
    req.states.push_back(s);
  }
  evaluateWear(wheels, Preset::kFast, req, &res);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.results.size(), std::size(cases));
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    EXPECT_EQ(res.results[i].status, tread_wear::WheelWearRate::STATUS_INVALID_INPUT) << cases[i].error;
    EXPECT_EQ(res.results[i].error, cases[i].error);
    EXPECT_EQ(res.results[i].wear_rate_kg_per_m, 0.0);
  }
}

TEST(EvaluateWear, ZeroLoadIsAWheelOffTheGround) {
  const auto wheels = pipelines(twoWheels());
  tread_wear::EvaluateWear::Request req;
  tread_wear::EvaluateWear::Response res;
  req.wheel = "a";
  req.states.push_back(rigState());
  req.states[0].load_n = 0.0;
  evaluateWear(wheels, Preset::kFast, req, &res);
  ASSERT_EQ(res.results.size(), 1u);
  EXPECT_EQ(res.results[0].status, tread_wear::WheelWearRate::STATUS_OK);
  EXPECT_EQ(res.results[0].error, "");
  EXPECT_EQ(res.results[0].wear_rate_kg_per_m, 0.0);
  EXPECT_EQ(res.results[0].fy_n, 0.0);
  EXPECT_EQ(res.results[0].stick_fraction, 1.0);
}

TEST(EvaluateWear, EqualsTheLoopOnTheSameInputsAndOneStatusEnumeration) {
  NodeConfig c = twoWheels();
  std::vector<std::unique_ptr<WheelPipeline>> wheels;
  wheels.push_back(std::make_unique<WheelPipeline>(c.wheels[0], temperatureTire(), c));
  feed(wheels[0].get(), 1.0, 90.0);
  const WheelOutput out = wheels[0]->step(1.0, stepSettings(Preset::kStandard, 0.0));
  tread_wear::EvaluateWear::Request req;
  tread_wear::EvaluateWear::Response res;
  req.wheel = "a";
  req.states.push_back(rigState());
  req.states[0].tread_temperature_c = 90.0;
  req.states.push_back(rigState());
  req.states[1].speed_mps = 0.01;  // below min_speed_mps
  evaluateWear(wheels, Preset::kStandard, req, &res);
  ASSERT_TRUE(res.success);
  EXPECT_EQ(res.preset, "standard");
  EXPECT_EQ(res.results[0].status, tread_wear::WheelWearRate::STATUS_OK);
  EXPECT_EQ(res.results[0].wear_rate_kg_per_m, out.result.wear_rate_kg_per_m);
  EXPECT_EQ(res.results[0].fx_n, out.result.fx_n);
  EXPECT_EQ(res.results[0].mz_nm, out.result.mz_nm);
  EXPECT_EQ(res.results[1].status, tread_wear::WheelWear::STATUS_LOW_SPEED);
  // One enumeration: the planner's codes are the live message's.
  EXPECT_EQ(+tread_wear::WheelWearRate::STATUS_INVALID_INPUT, +tread_wear::WheelWear::STATUS_INVALID_INPUT);
  EXPECT_EQ(+tread_wear::WheelWearRate::STATUS_LOW_SPEED, +tread_wear::WheelWear::STATUS_LOW_SPEED);
  EXPECT_EQ(statusCode(WheelStatus::kInvalidInput), tread_wear::WheelWear::STATUS_INVALID_INPUT);
}

TEST(EvaluateWear, UnknownWheelOrPresetFails) {
  const auto wheels = pipelines(twoWheels());
  tread_wear::EvaluateWear::Request req;
  tread_wear::EvaluateWear::Response res;
  req.wheel = "nope";
  evaluateWear(wheels, Preset::kFast, req, &res);
  EXPECT_FALSE(res.success);
  EXPECT_EQ(res.message, "unknown wheel 'nope'");
  req.wheel = "a";
  req.preset = "turbo";
  evaluateWear(wheels, Preset::kFast, req, &res);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("turbo"), std::string::npos);
}

TEST(ResetWheel, ChangesTheTireAndRejectsBadIds) {
  const auto wheels = pipelines(twoWheels());
  wheels[1]->restore({"b", "old", 1e-6, 12.0, 0.0});
  tread_wear::ResetWheel::Request req;
  tread_wear::ResetWheel::Response res;
  req.wheel = "b";
  req.tire_id = "new";
  ASSERT_TRUE(resetWheel(wheels, 100.0, req, &res));
  EXPECT_TRUE(res.success);
  EXPECT_EQ(res.previous_loss_kg, 1e-6);
  EXPECT_EQ(res.previous_distance_m, 12.0);
  EXPECT_NE(res.message.find("old -> new"), std::string::npos) << res.message;
  EXPECT_EQ(wheels[1]->record().reset_unix_s, 100.0);
  req.tire_id = "";
  EXPECT_FALSE(resetWheel(wheels, 100.0, req, &res));
  req.tire_id = std::string(kMaxTireIdLength + 1, 'x');
  EXPECT_FALSE(resetWheel(wheels, 100.0, req, &res));
  req.wheel = "c";
  req.tire_id = "x";
  EXPECT_FALSE(resetWheel(wheels, 100.0, req, &res));
  EXPECT_EQ(res.message, "unknown wheel 'c'");
}

// ---------------------------------------------------------------------------------------------------------
// Persistence and its diagnostic.

std::string tempPath(const std::string& tag) {
  return testing::TempDir() + "tread_wear_parts_" + std::to_string(getpid()) + "_" + tag;
}

TEST(NodePersistence, ADirectoryAtTheStatePathIsAnIoErrorAndLeftAlone) {
  const std::string path = tempPath("state_dir.json");
  ASSERT_EQ(mkdir(path.c_str(), 0755), 0);
  const auto wheels = pipelines(twoWheels());
  NodePersistence persistence(path);
  persistence.restore(wheels);
  const NodePersistence::Status s = persistence.status();
  EXPECT_EQ(s.restore, "io_error");
  EXPECT_FALSE(s.saving) << "a path that cannot be read must not be written";
  EXPECT_NE(s.problem.find("is a directory"), std::string::npos) << s.problem;
  EXPECT_EQ(s.problem.find("corrupt"), std::string::npos) << s.problem;
  persistence.save(wheels, "test");
  struct stat st;
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode)) << "the directory stays where it was";
  LoopStatus loop;
  NodeReconfigure reconfigure(twoWheels(), &loop);
  NodeDiagnostics diagnostics(wheels, loop, persistence, reconfigure);
  diagnostic_updater::DiagnosticStatusWrapper stat_msg;
  diagnostics.diagnosePersistence(stat_msg);
  EXPECT_EQ(stat_msg.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  rmdir(path.c_str());
}

TEST(NodePersistence, WhatIsSavedIsRestored) {
  const std::string path = tempPath("state.json");
  std::remove(path.c_str());
  {
    const auto wheels = pipelines(twoWheels());
    wheels[0]->restore({"a", "tire-x", 3e-6, 40.0, 99.0});
    NodePersistence persistence(path);
    persistence.restore(wheels);
    EXPECT_EQ(persistence.status().restore, "missing");
    persistence.save(wheels, "test");
    EXPECT_GE(persistence.status().seconds_since_save, 0.0);
  }
  const auto wheels = pipelines(twoWheels());
  NodePersistence persistence(path);
  persistence.restore(wheels);
  EXPECT_EQ(persistence.status().restore, "loaded");
  EXPECT_EQ(wheels[0]->record().accumulated_loss_kg, 3e-6);
  EXPECT_EQ(wheels[0]->record().tire_id, "tire-x");
  EXPECT_EQ(wheels[1]->record().tire_id, "tire-b");
  std::remove(path.c_str());
}

// ---------------------------------------------------------------------------------------------------------
// Reconfigure: the start-up validation, rejections reported and nothing clamped.

TEST(NodeReconfigure, RejectsWhatStartUpRejectsAndKeepsTheValues) {
  NodeConfig c = twoWheels();  // 50 Hz, max_step_s 0.6
  c.marker_rate_hz = 10.0;
  LoopStatus loop;
  NodeReconfigure reconfigure(c, &loop);
  EXPECT_DOUBLE_EQ(loop.period_s.load(), 0.02);
  struct Case {
    double rate_hz, budget_us;
    const char* preset;
    const char* error;
  };
  const Case cases[] = {
      {0.5, 0.0, "fast", "update_rate_hz = 0.5: must be >= 2 / max_step_s"},  // was clamped to 1
      {5000.0, 0.0, "fast", "update_rate_hz = 5000: must be in (0, 1000]"},  // was clamped to 1000
      {5.0, 0.0, "fast", "marker_rate_hz = 10: must be in [0, update_rate_hz = 5]"},  // start-up rejects it too
      {50.0, -5.0, "fast", "budget_us = -5: must be finite and >= 0"},
      {50.0, 0.0, "turbo", "preset = turbo: must be fast, standard, fine or reference"},
  };
  for (const Case& k : cases) {
    tread_wear::TreadWearConfig request = reconfigure.current();
    request.update_rate_hz = k.rate_hz;
    request.budget_us = k.budget_us;
    request.preset = k.preset;
    EXPECT_FALSE(reconfigure.apply(&request)) << k.error;
    EXPECT_EQ(reconfigure.lastRejection().rfind(k.error, 0), 0u) << reconfigure.lastRejection();
    EXPECT_EQ(request.update_rate_hz, 50.0) << "the answer carries the values kept";
    EXPECT_EQ(request.budget_us, 0.0);
    EXPECT_EQ(request.preset, "fast");
    EXPECT_DOUBLE_EQ(loop.period_s.load(), 0.02);
    NodeConfig startup = c;
    startup.update_rate_hz = k.rate_hz;
    startup.budget_us = k.budget_us;
    if (parsePreset(k.preset, &startup.model.preset)) {
      EXPECT_FALSE(startup.validate(nullptr)) << "the same rule at start-up";
    }
  }
  // The rejection shows in the loop's diagnostic until a request is applied.
  const auto wheels = pipelines(c);
  NodePersistence persistence("");
  NodeDiagnostics diagnostics(wheels, loop, persistence, reconfigure);
  diagnostic_updater::DiagnosticStatusWrapper stat;
  diagnostics.diagnoseLoop(stat);
  EXPECT_EQ(stat.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(stat.message.find("reconfigure rejected: preset"), std::string::npos) << stat.message;

  tread_wear::TreadWearConfig request = reconfigure.current();
  request.update_rate_hz = 20.0;
  request.budget_us = 300.0;
  request.preset = "standard";
  EXPECT_TRUE(reconfigure.apply(&request));
  EXPECT_EQ(reconfigure.lastRejection(), "");
  EXPECT_DOUBLE_EQ(loop.period_s.load(), 0.05);
  EXPECT_EQ(loop.budget_us.load(), 300.0);
  EXPECT_EQ(loop.configuredPreset(), Preset::kStandard);
  EXPECT_EQ(reconfigure.current().update_rate_hz, 20.0);
  diagnostic_updater::DiagnosticStatusWrapper ok;
  diagnostics.diagnoseLoop(ok);
  EXPECT_EQ(ok.level, diagnostic_msgs::DiagnosticStatus::OK);
}

// ---------------------------------------------------------------------------------------------------------
// Diagnostics of a wheel.

TEST(NodeDiagnostics, AWheelReportsItsInputsAndRejects) {
  const NodeConfig c = twoWheels();
  const auto wheels = pipelines(c);
  LoopStatus loop;
  NodeReconfigure reconfigure(c, &loop);
  NodePersistence persistence("");
  NodeDiagnostics diagnostics(wheels, loop, persistence, reconfigure);
  feed(wheels[0].get(), 1.0);
  wheels[0]->step(1.0, stepSettings(Preset::kFast, 0.0));
  diagnostic_updater::DiagnosticStatusWrapper first;
  diagnostics.diagnoseWheel(0, 1.25, 100.0, first);
  EXPECT_EQ(first.level, diagnostic_msgs::DiagnosticStatus::OK) << first.message;
  wheels[0]->setLoad(1.3, -5.0);
  diagnostic_updater::DiagnosticStatusWrapper second;
  diagnostics.diagnoseWheel(0, 1.5, 101.0, second);
  EXPECT_EQ(second.level, diagnostic_msgs::DiagnosticStatus::WARN);
  std::map<std::string, std::string> values;
  for (const auto& kv : second.values) values[kv.key] = kv.value;
  EXPECT_EQ(values["tire_id"], "tire-a");
  EXPECT_EQ(values["load rejected"], "1");
  EXPECT_EQ(values["invalid: negative_load"], "1");
  EXPECT_EQ(values["load rate [Hz]"], "1.0");
  EXPECT_EQ(values["speed age [s]"], "0.500");
  EXPECT_EQ(values["tread_temperature age [s]"], "never received");
  EXPECT_EQ(values["preset"], "fast");
}

TEST(NodeDiagnostics, TimeLostBetweenTwoReportsIsWarnAndAboveTheShareError) {
  ros::Time::init();  // the throttled warning of lost time reads ros::Time
  const NodeConfig c = twoWheels();  // 50 Hz, stale_timeout_s 0.3 s, max_step_s 0.6 s
  const auto wheels = pipelines(c);
  LoopStatus loop;
  NodeReconfigure reconfigure(c, &loop);
  NodePersistence persistence("");
  NodeDiagnostics diagnostics(wheels, loop, persistence, reconfigure);
  // Steps k0..k1 of 20 ms, inputs 10 ms before each (no age lands on the timeout); wheel a gets none where
  // gap_a(t) holds, b always does.
  auto run = [&](int k0, int k1, const std::function<bool(double)>& gap_a) {
    for (int k = k0; k <= k1; ++k) {
      const double t = 0.02 * k;
      if (!gap_a(t)) feed(wheels[0].get(), t - 0.01);
      feed(wheels[1].get(), t - 0.01);
      for (const auto& w : wheels) w->step(t, stepSettings(Preset::kFast, 0.0));
    }
  };
  struct Report {
    int level;
    std::string message;
    std::map<std::string, std::string> values;
  };
  auto report = [&](std::size_t wheel, double t) {
    diagnostic_updater::DiagnosticStatusWrapper stat;
    diagnostics.diagnoseWheel(wheel, t, 100.0 + t, stat);
    Report r{stat.level, stat.message, {}};
    for (const auto& kv : stat.values) r.values[kv.key] = kv.value;
    return r;
  };
  auto vehicle = [&] {
    diagnostic_updater::DiagnosticStatusWrapper stat;
    diagnostics.diagnoseVehicle(stat);
    return Report{stat.level, stat.message, {}};
  };
  auto never = [](double) { return false; };

  run(0, 50, never);  // 0 to 1 s, all integrated
  EXPECT_EQ(report(0, 1.0).level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(report(1, 1.0).level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(vehicle().level, diagnostic_msgs::DiagnosticStatus::OK);

  // 1 to 2 s: a's inputs pause after 0.99 s until 1.39 s: the steps from 1.30 s find them stale, the one at
  // 1.40 s fresh again; (1.28, 1.40] is lost.
  run(51, 100, [](double t) { return t > 1.01 && t < 1.39; });
  Report gap = report(0, 2.0);
  EXPECT_EQ(gap.values["status"], "ok") << "fine at the instant of the report";
  EXPECT_EQ(gap.level, diagnostic_msgs::DiagnosticStatus::WARN) << gap.message;
  EXPECT_EQ(gap.values["unintegrated since last report [s]"], "0.120");
  EXPECT_EQ(gap.values["unintegrated since last report: stale_input [s]"], "0.120");
  EXPECT_EQ(gap.values["integrated since last report [s]"], "0.880");
  EXPECT_NE(gap.message.find("0.120 s of 1.000 s not integrated (stale_input 0.120 s)"), std::string::npos)
      << gap.message;
  EXPECT_EQ(report(1, 2.0).level, diagnostic_msgs::DiagnosticStatus::OK);
  const Report incomplete = vehicle();
  EXPECT_EQ(incomplete.level, diagnostic_msgs::DiagnosticStatus::WARN) << incomplete.message;
  EXPECT_NE(incomplete.message.find("loss incomplete"), std::string::npos) << incomplete.message;
  EXPECT_NE(incomplete.message.find("a 0.120 s"), std::string::npos) << incomplete.message;
  EXPECT_EQ(incomplete.message.find("b "), std::string::npos) << "b integrated everything: " << incomplete.message;

  // 2 to 3 s: the clock jumps from 2.2 to 2.9 s (> max_step_s): 0.7 of 1 s lost, above the ERROR share.
  run(101, 110, never);
  run(145, 150, never);
  Report jump = report(0, 3.0);
  EXPECT_EQ(jump.level, diagnostic_msgs::DiagnosticStatus::ERROR) << jump.message;
  EXPECT_EQ(jump.values["unintegrated since last report: time_jump [s]"], "0.700");
  EXPECT_EQ(vehicle().level, diagnostic_msgs::DiagnosticStatus::ERROR);

  // 3 to 4 s: all integrated again.
  run(151, 200, never);
  EXPECT_EQ(report(0, 4.0).level, diagnostic_msgs::DiagnosticStatus::OK);
  const Report complete = vehicle();
  EXPECT_EQ(complete.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(complete.message, "loss complete");
}

// ---------------------------------------------------------------------------------------------------------
// Markers.

TEST(WearMarkers, APatchIsDrawnAsCellsAndALabel) {
  WearModelOptions options;
  options.preset = Preset::kFast;
  const WearModel model(loadTireParams(kTireFile), options);
  OperatingPoint op;
  op.load_n = kLoad;
  op.speed_mps = kSpeed;
  op.slip_angle_rad = -10.0 * units::kDegree;
  op.path_curvature_per_m = kCurvature;
  const BrushWearModel& solver = model.solver(Preset::kFast);
  PatchFields fields;
  fields.resize(solver.nodesX(), solver.strips());
  WearResult r;
  model.evaluate(op, &r, &fields);
  WheelOutput out;
  out.status = WheelStatus::kOk;
  out.accumulated_loss_kg = 1.5e-6;
  out.distance_m = 2500.0;
  out.result = r;
  visualization_msgs::MarkerArray array;
  appendWheelMarkers("fl", "wheel_fl", ros::Time(5.0), fields, r, out, &array);
  ASSERT_EQ(array.markers.size(), 3u);
  const std::size_t cells = static_cast<std::size_t>((fields.n_x_nodes - 1) * fields.n_strips);
  EXPECT_EQ(array.markers[0].ns, "fl/wear");
  EXPECT_EQ(array.markers[1].ns, "fl/zones");
  EXPECT_EQ(array.markers[2].ns, "fl/label");
  for (int m = 0; m < 2; ++m) {
    EXPECT_EQ(array.markers[m].type, visualization_msgs::Marker::TRIANGLE_LIST);
    EXPECT_EQ(array.markers[m].points.size(), 6 * cells);
    EXPECT_EQ(array.markers[m].colors.size(), 6 * cells);
    EXPECT_EQ(array.markers[m].header.frame_id, "wheel_fl");
  }
  // The zones sit beside the patch, 2.5 half widths to +y.
  double min_y = 1e9;
  for (const auto& p : array.markers[1].points) min_y = std::min(min_y, p.y);
  EXPECT_NEAR(min_y, 1.5 * r.half_width_m, 1e-12);
  // At -10 deg the trailing part slides: both red (slide) and green (exact stick) cells.
  bool red = false, green = false;
  for (const auto& c : array.markers[1].colors) {
    red = red || (c.r > 0.8f && c.g < 0.2f);
    green = green || (c.g > 0.6f && c.r < 0.2f);
  }
  EXPECT_TRUE(red && green);
  EXPECT_EQ(array.markers[2].text, "fl (ok)\n1.500 mg, 2.500 km, slide " +
                                       std::to_string(static_cast<int>(std::lround(100.0 * r.slide_fraction))) + "%");
  EXPECT_GE(array.markers[2].scale.z, 0.01);

  visualization_msgs::MarkerArray label_only;
  appendWheelMarkers("fl", "wheel_fl", ros::Time(5.0), PatchFields(), r, out, &label_only);
  ASSERT_EQ(label_only.markers.size(), 1u);
  EXPECT_EQ(label_only.markers[0].ns, "fl/label");
}

TEST(WearMarkers, EachWheelIsDrawnFromItsLastStep) {
  const NodeConfig c = twoWheels();
  const auto wheels = pipelines(c);
  WearMarkers markers(wheels);
  feed(wheels[0].get(), 1.0);
  wheels[0]->step(1.0, stepSettings(Preset::kFast, 0.0));  // wheel b: never evaluated
  visualization_msgs::MarkerArray array;
  markers.build(ros::Time(1.0), &array);
  ASSERT_EQ(array.markers.size(), 4u);
  EXPECT_EQ(array.markers[0].ns, "a/wear");
  EXPECT_EQ(array.markers[3].ns, "b/label");
  EXPECT_NE(array.markers[3].text.find("no_input"), std::string::npos);

  // Wheel a off the ground: no patch, the label only.
  wheels[0]->setLoad(1.02, 0.0);
  wheels[0]->step(1.02, stepSettings(Preset::kFast, 0.0));
  visualization_msgs::MarkerArray lifted;
  markers.build(ros::Time(1.02), &lifted);
  ASSERT_EQ(lifted.markers.size(), 2u);
  EXPECT_EQ(lifted.markers[0].ns, "a/label");
}

// ---------------------------------------------------------------------------------------------------------
// Realtime publisher.

/// Records what the publisher thread hands over; blocks it while `hold` is set.
struct Recorder {
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<double> received;
  bool hold = false;
  bool in_sink = false;

  void sink(const tread_wear::WheelWear& m) {
    std::unique_lock<std::mutex> lock(mutex);
    in_sink = true;
    cv.notify_all();
    cv.wait(lock, [this] { return !hold; });
    received.push_back(m.wear_rate_kg_per_m);
    in_sink = false;
    cv.notify_all();
  }
  bool waitFor(const std::function<bool()>& pred) {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, std::chrono::seconds(5), pred);
  }
};

bool publish(RealtimePublisher<tread_wear::WheelWear>* p, double value) {
  if (!p->trylock()) return false;
  p->msg().wear_rate_kg_per_m = value;
  p->unlockAndPublish();
  return true;
}

TEST(RealtimePublisher, HandsEachMessageOverOnceAndSkipsWhileBusy) {
  Recorder rec;
  RealtimePublisher<tread_wear::WheelWear> p([&rec](const tread_wear::WheelWear& m) { rec.sink(m); });
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.hold = true;
  }
  ASSERT_TRUE(publish(&p, 1.0));
  ASSERT_TRUE(rec.waitFor([&] { return rec.in_sink; }));  // the thread publishes 1 (and is held there)
  EXPECT_TRUE(publish(&p, 2.0)) << "the slot is free while the thread publishes its copy";
  EXPECT_FALSE(publish(&p, 3.0)) << "2 is not taken yet: the loop skips instead of waiting";
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.hold = false;
    rec.cv.notify_all();
  }
  ASSERT_TRUE(rec.waitFor([&] { return rec.received.size() == 2 && !rec.in_sink; }));
  EXPECT_EQ(rec.received, (std::vector<double>{1.0, 2.0}));
  p.stop();
  p.stop();  // idempotent
}

TEST(RealtimePublisher, TheLoopSideAllocatesNothing) {
  std::atomic<int> count{0};
  RealtimePublisher<tread_wear::WheelWear> p([&count](const tread_wear::WheelWear&) { ++count; });
  p.msg().tire_id.reserve(kMaxTireIdLength + 1);
  const long before = t_allocations;
  int published = 0;
  for (int k = 0; k < 1000; ++k) {
    if (!p.trylock()) continue;
    p.msg().wear_rate_kg_per_m = k;
    p.msg().tire_id = "tire-a";
    p.unlockAndPublish();
    ++published;
  }
  EXPECT_EQ(t_allocations - before, 0);
  EXPECT_GT(published, 0);
  p.stop();
  EXPECT_LE(count.load(), published);
}

TEST(RealtimePublisher, StopsWhileIdleAndWhileAMessageWaits) {
  for (int k = 0; k < 200; ++k) {  // a lost wake-up would hang here
    RealtimePublisher<tread_wear::WheelWear> p([](const tread_wear::WheelWear&) {});
    if (k % 2) publish(&p, 1.0);
  }
  SUCCEED();
}

// ---------------------------------------------------------------------------------------------------------
// --help.

TEST(NodeHelp, ListsEveryParameterTopicAndService) {
  const std::string help = nodeHelp();
  for (const char* key : {"update_rate_hz", "marker_rate_hz", "budget_us", "preset", "turn_slip_orientation",
                          "min_speed_mps", "stale_timeout_s", "max_step_s", "limits/max_load_n",
                          "limits/max_abs_slip_angle_rad", "limits/max_abs_slip_ratio",
                          "limits/max_abs_path_curvature_per_m", "limits/max_speed_mps", "limits/min_temperature_c",
                          "limits/max_temperature_c", "state_file", "save_interval_s", "base_frame", "config_dir",
                          "wheels", "wheels/<name>/load", "wheels/<name>/wear", "wear_markers", "evaluate_wear",
                          "reset_wheel", "set_parameters"})
    EXPECT_NE(help.find(key), std::string::npos) << key;
  EXPECT_NE(help.find("update_rate_hz [Hz] = 100:"), std::string::npos) << "defaults come from the table";
}

TEST(NodeHelp, TheBinaryPrintsItAndExitsZeroWithoutAMaster) {
  FILE* out = popen("env ROS_MASTER_URI=http://127.0.0.1:1 " TREAD_WEAR_NODE_BINARY " --help", "r");
  ASSERT_NE(out, nullptr);
  std::string text;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof(buf), out)) text.append(buf, n);
  const int status = pclose(out);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_EQ(text, nodeHelp());
}

}  // namespace
}  // namespace tread_wear
