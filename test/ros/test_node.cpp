// tread_wear_node through ROS: inputs in -> outputs out, stale and invalid inputs, time jumps, the planner and
// reset services, kill -9 + restart, and a bag regression. One binary; each .test file selects its cases with
// --gtest_filter and configures the node (test/ros/*.test). Expected values come from the core library
// evaluated directly (WearModel on the same tire file), never from the node's own output.
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosgraph_msgs/Clock.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tread_wear/EvaluateWear.h"
#include "tread_wear/ResetWheel.h"
#include "tread_wear/VehicleWear.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/WheelWear.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/state_store.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

const std::string kTireFile = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";

// The rig point of paper Table 3 (75 N, alpha = -2 deg, R_t = 60 mm) at 0.5 m/s.
constexpr double kLoad = 75.0, kSpeed = 0.5, kCurvature = 1.0 / 0.060;
const double kSlipAngle = -2.0 * units::kDegree;

/// The rig point the tests publish: 75 N, 0.5 m/s, alpha = -2 deg on the 60 mm track.
OperatingPoint rigPoint() {
  OperatingPoint op;
  op.load_n = kLoad;
  op.speed_mps = kSpeed;
  op.slip_angle_rad = kSlipAngle;
  op.path_curvature_per_m = kCurvature;
  return op;
}

/// W_r [kg/m] etc. of the rig point from the core library directly, fast preset as configured in the tests.
WearResult directResult(Preset preset = Preset::kFast) {
  WearModelOptions o;
  o.preset = preset;
  WearModel model(loadTireParams(kTireFile), o);
  WearResult r;
  model.evaluate(rigPoint(), &r);
  return r;
}

/// Publishes a wheel's inputs and records its outputs and the diagnostics.
class Harness {
 public:
  explicit Harness(const std::string& wheel) : wheel_(wheel) {
    load_ = nh_.advertise<tread_wear::WheelLoad>("wheels/" + wheel + "/load", 10);
    slip_ = nh_.advertise<tread_wear::WheelSlip>("wheels/" + wheel + "/slip", 10);
    speed_ = nh_.advertise<tread_wear::WheelSpeed>("wheels/" + wheel + "/speed", 10);
    wear_sub_ = nh_.subscribe("wheels/" + wheel + "/wear", 100, &Harness::onWear, this);
    diag_sub_ = nh_.subscribe("/diagnostics", 100, &Harness::onDiag, this);
  }
  void publish(double load = kLoad, double speed = kSpeed, bool with_speed = true) {
    tread_wear::WheelLoad l;
    l.load_n = load;
    tread_wear::WheelSlip s;
    s.slip_angle_rad = kSlipAngle;
    s.path_curvature_per_m = kCurvature;
    tread_wear::WheelSpeed v;
    v.speed_mps = speed;
    load_.publish(l);
    slip_.publish(s);
    if (with_speed) speed_.publish(v);
  }
  /// Spins (publishing each 10 ms when asked) until pred holds or timeout [s, wall].
  bool spinUntil(const std::function<bool()>& pred, double timeout_s, bool keep_publishing = true,
                 double load = kLoad) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      if (keep_publishing) publish(load);
      ros::WallDuration(0.01).sleep();
      ros::spinOnce();
      if (pred()) return true;
    }
    return false;
  }
  tread_wear::WheelWear last() {
    std::lock_guard<std::mutex> l(mutex_);
    return last_;
  }
  int count() {
    std::lock_guard<std::mutex> l(mutex_);
    return count_;
  }
  /// Messages received with this status (a status may last a single cycle, between two spins).
  int seen(int status) {
    std::lock_guard<std::mutex> l(mutex_);
    return status_count_[status];
  }
  /// Value of a key in the last diagnostic status named "...wheel <name>", or "".
  std::string diag(const std::string& key, int* level = nullptr) {
    std::lock_guard<std::mutex> l(mutex_);
    if (level) *level = diag_level_;
    auto it = diag_.find(key);
    return it == diag_.end() ? "" : it->second;
  }
  /// Reports of the wheel received so far, the message of the last one.
  int diagCount() {
    std::lock_guard<std::mutex> l(mutex_);
    return diag_count_;
  }
  std::string diagMessage() {
    std::lock_guard<std::mutex> l(mutex_);
    return diag_message_;
  }
  /// Level and message of the last "...vehicle" status (-1 before any).
  int vehicleLevel(std::string* message) {
    std::lock_guard<std::mutex> l(mutex_);
    *message = vehicle_message_;
    return vehicle_level_;
  }
  bool waitForNode(double timeout_s) {
    return spinUntil([this] { return load_.getNumSubscribers() > 0 && count() > 0; }, timeout_s, false);
  }

 private:
  void onWear(const tread_wear::WheelWear::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    last_ = *m;
    ++count_;
    ++status_count_[m->status];
  }
  void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    auto endsWith = [](const std::string& name, const std::string& suffix) {
      return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    for (const auto& s : m->status) {
      if (endsWith(s.name, ": vehicle")) {
        vehicle_level_ = s.level;
        vehicle_message_ = s.message;
      }
      if (!endsWith(s.name, "wheel " + wheel_)) continue;
      diag_.clear();
      for (const auto& kv : s.values) diag_[kv.key] = kv.value;
      diag_level_ = s.level;
      diag_message_ = s.message;
      ++diag_count_;
    }
  }

  std::string wheel_;
  ros::NodeHandle nh_;
  ros::Publisher load_, slip_, speed_;
  ros::Subscriber wear_sub_, diag_sub_;
  std::mutex mutex_;
  tread_wear::WheelWear last_;
  int count_ = 0;
  std::map<int, int> status_count_;
  std::map<std::string, std::string> diag_;
  int diag_level_ = -1;
  int diag_count_ = 0;
  std::string diag_message_;
  int vehicle_level_ = -1;
  std::string vehicle_message_;
};

// Relative tolerance for the node's wear rate against the direct evaluation: both run the same
// deterministic code on the same doubles (messages carry float64), so only rounding could differ.
constexpr double kSameModelRelTol = 1e-12;

TEST(NodeIo, InputsInOutputsOut) {
  Harness h("a");
  ASSERT_TRUE(h.waitForNode(10.0));
  ros::NodeHandle nh;
  tread_wear::VehicleWear vehicle;
  int vehicle_count = 0;
  ros::Subscriber vs =
      nh.subscribe<tread_wear::VehicleWear>("wear", 10, [&](const tread_wear::VehicleWear::ConstPtr& m) {
        vehicle = *m;
        ++vehicle_count;
      });
  ASSERT_TRUE(h.spinUntil(
      [&] { return h.last().status == tread_wear::WheelWear::STATUS_OK && h.last().accumulated_loss_kg > 0.0; }, 10.0));
  const WearResult direct = directResult();
  const tread_wear::WheelWear m = h.last();
  EXPECT_EQ(m.wheel, "a");
  EXPECT_EQ(m.header.frame_id, "wheel_a");
  EXPECT_EQ(m.tire_id, "tire-a");
  EXPECT_EQ(m.preset, "fast");
  EXPECT_FALSE(m.degraded);
  EXPECT_NEAR(m.wear_rate_kg_per_m, direct.wear_rate_kg_per_m, kSameModelRelTol * direct.wear_rate_kg_per_m);
  EXPECT_NEAR(m.wear_rate_kg_per_s, direct.wear_rate_kg_per_s, kSameModelRelTol * direct.wear_rate_kg_per_s);
  EXPECT_NEAR(m.fy_n, direct.fy_n, kSameModelRelTol * std::fabs(direct.fy_n));
  EXPECT_NEAR(m.slide_fraction, direct.slide_fraction, 1e-12);
  // Constant inputs: accumulated loss / distance is W_r (trapezoid of a constant is exact).
  ASSERT_GT(m.distance_m, 0.0);
  EXPECT_NEAR(m.accumulated_loss_kg / m.distance_m, direct.wear_rate_kg_per_m, 1e-9 * direct.wear_rate_kg_per_m);
  EXPECT_GT(m.remaining_tread_depth_m, 0.0);
  ASSERT_TRUE(h.spinUntil([&] { return vehicle_count > 0; }, 5.0));
  ASSERT_EQ(vehicle.wheels.size(), 2u);
  EXPECT_EQ(vehicle.wheels[0].wheel, "a");
  EXPECT_EQ(vehicle.wheels[1].wheel, "b");
  EXPECT_NEAR(vehicle.total_accumulated_loss_kg,
              vehicle.wheels[0].accumulated_loss_kg + vehicle.wheels[1].accumulated_loss_kg, 1e-18);
}

TEST(NodeIo, InvalidInputIsCountedAndNeverUsed) {
  Harness h("b");
  ASSERT_TRUE(h.waitForNode(10.0));
  ASSERT_TRUE(h.spinUntil([&] { return h.last().status == tread_wear::WheelWear::STATUS_OK; }, 10.0));
  // NaN load: the wheel stops being evaluated, its loss freezes.
  ASSERT_TRUE(h.spinUntil([&] { return h.last().status == tread_wear::WheelWear::STATUS_INVALID_INPUT; }, 5.0, true,
                          std::numeric_limits<double>::quiet_NaN()));
  const double frozen = h.last().accumulated_loss_kg;
  h.spinUntil([] { return false; }, 0.3, true, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(h.last().accumulated_loss_kg, frozen);
  EXPECT_EQ(h.last().status, tread_wear::WheelWear::STATUS_INVALID_INPUT);
  // Negative load: same, and classified separately.
  h.spinUntil([] { return false; }, 0.3, true, -100.0);
  EXPECT_EQ(h.last().accumulated_loss_kg, frozen);
  int level = -1;
  ASSERT_TRUE(h.spinUntil([&] { return !h.diag("invalid: negative_load").empty(); }, 5.0, true, -100.0));
  EXPECT_GT(std::stoi(h.diag("invalid: not_finite", &level)), 0);
  EXPECT_GT(std::stoi(h.diag("invalid: negative_load")), 0);
  // The report covers time lost to invalid inputs since the previous one: WARN, or ERROR when that was most of it.
  EXPECT_GE(level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_GT(std::stod(h.diag("unintegrated since last report: invalid_input [s]")), 0.0);
  // Valid again: estimation resumes.
  ASSERT_TRUE(h.spinUntil([&] { return h.last().accumulated_loss_kg > frozen; }, 5.0));
}

TEST(NodeIo, StaleInputStopsIntegration) {
  Harness h("b");
  ASSERT_TRUE(h.waitForNode(10.0));
  ASSERT_TRUE(h.spinUntil([&] { return h.last().status == tread_wear::WheelWear::STATUS_OK; }, 10.0));
  // Stop publishing: after the 0.3 s timeout (node.test) the wheel is stale and its loss constant.
  ASSERT_TRUE(h.spinUntil([&] { return h.last().status == tread_wear::WheelWear::STATUS_STALE_INPUT; }, 3.0, false));
  const double frozen = h.last().accumulated_loss_kg;
  h.spinUntil([] { return false; }, 0.5, false);
  EXPECT_EQ(h.last().accumulated_loss_kg, frozen);
  EXPECT_GT(h.last().unaccounted_time_s, 0.0);
  ASSERT_TRUE(h.spinUntil([&] { return h.diag("status") == "stale_input" && !h.diag("stale steps").empty() &&
                                       std::stoul(h.diag("stale steps")) > 0; }, 5.0, false));
}

TEST(NodeIo, PlannerServiceMatchesTheCore) {
  ros::NodeHandle nh;
  ASSERT_TRUE(ros::service::waitForService("evaluate_wear", ros::Duration(10.0)));
  tread_wear::EvaluateWear srv;
  srv.request.wheel = "a";
  srv.request.preset = "standard";
  tread_wear::WheelState s;
  s.load_n = kLoad;
  s.speed_mps = kSpeed;
  s.slip_angle_rad = kSlipAngle;
  s.path_curvature_per_m = kCurvature;
  s.tread_temperature_c = std::numeric_limits<double>::quiet_NaN();
  srv.request.states.push_back(s);
  tread_wear::WheelState bad = s;
  bad.speed_mps = -1.0;
  srv.request.states.push_back(bad);
  tread_wear::WheelState airborne = s;
  airborne.load_n = 0.0;
  srv.request.states.push_back(airborne);
  tread_wear::WheelState beyond_limits = s;  // the live topics reject it (limits/max_abs_path_curvature_per_m 100)
  beyond_limits.path_curvature_per_m = 500.0;
  srv.request.states.push_back(beyond_limits);
  ASSERT_TRUE(ros::service::call("evaluate_wear", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.preset, "standard");
  ASSERT_EQ(srv.response.results.size(), 4u);
  const WearResult direct = directResult(Preset::kStandard);
  EXPECT_EQ(srv.response.results[0].status, tread_wear::WheelWearRate::STATUS_OK);
  EXPECT_NEAR(srv.response.results[0].wear_rate_kg_per_m, direct.wear_rate_kg_per_m,
              kSameModelRelTol * direct.wear_rate_kg_per_m);
  EXPECT_NEAR(srv.response.results[0].fy_n, direct.fy_n, kSameModelRelTol * std::fabs(direct.fy_n));
  EXPECT_EQ(srv.response.results[1].status, tread_wear::WheelWearRate::STATUS_INVALID_INPUT);
  EXPECT_NE(srv.response.results[1].error.find("speed_mps"), std::string::npos);
  EXPECT_EQ(srv.response.results[2].status, tread_wear::WheelWearRate::STATUS_OK);
  EXPECT_EQ(srv.response.results[2].wear_rate_kg_per_m, 0.0);
  EXPECT_EQ(srv.response.results[3].status, tread_wear::WheelWear::STATUS_INVALID_INPUT);
  EXPECT_NE(srv.response.results[3].error.find("limits/max_abs_path_curvature_per_m"), std::string::npos)
      << srv.response.results[3].error;

  srv.request.wheel = "nope";
  ASSERT_TRUE(ros::service::call("evaluate_wear", srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("nope"), std::string::npos);
}

TEST(NodeIo, ResetServiceStartsANewTire) {
  Harness h("a");
  ASSERT_TRUE(h.waitForNode(10.0));
  ASSERT_TRUE(h.spinUntil([&] { return h.last().accumulated_loss_kg > 0.0; }, 10.0));
  tread_wear::ResetWheel srv;
  srv.request.wheel = "a";
  srv.request.tire_id = "tire-a2";
  ASSERT_TRUE(ros::service::call("reset_wheel", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_GT(srv.response.previous_loss_kg, 0.0);
  ASSERT_TRUE(h.spinUntil([&] { return h.last().tire_id == "tire-a2"; }, 5.0));
  EXPECT_LT(h.last().accumulated_loss_kg, srv.response.previous_loss_kg);
  srv.request.tire_id = "";
  ASSERT_TRUE(ros::service::call("reset_wheel", srv));
  EXPECT_FALSE(srv.response.success);
}

// dynamic_reconfigure clamped update_rate_hz into [1, 1000] before the node saw it and the node accepted rates
// below marker_rate_hz; now a request that the start-up validation rejects changes nothing and says so.
TEST(NodeIo, ReconfigureRejectsWhatStartUpRejectsWithoutClamping) {
  const std::string service = "/tread_wear_node/set_parameters";
  ASSERT_TRUE(ros::service::waitForService(service, ros::Duration(10.0)));
  auto setRate = [&](double rate_hz) {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::DoubleParameter p;
    p.name = "update_rate_hz";
    p.value = rate_hz;
    srv.request.config.doubles.push_back(p);
    EXPECT_TRUE(ros::service::call(service, srv));
    for (const auto& d : srv.response.config.doubles)
      if (d.name == "update_rate_hz") return d.value;
    return std::numeric_limits<double>::quiet_NaN();
  };
  ros::NodeHandle nh;
  std::string loop_message, loop_rate;
  std::mutex mutex;
  ros::Subscriber ds = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& st : m->status)
          if (st.name.find("update loop") != std::string::npos) {
            loop_message = st.message;
            for (const auto& kv : st.values)
              if (kv.key == "update rate [Hz]") loop_rate = kv.value;
          }
      });
  // two_wheels.yaml: 50 Hz, marker_rate_hz 2, max_step_s 0.6 (so at least 2 / 0.6 = 3.3 Hz).
  for (double rejected : {0.5, 5000.0, 1.5}) EXPECT_EQ(setRate(rejected), 50.0) << rejected << " Hz";
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
  bool reported = false;
  while (!reported && ros::WallTime::now() < end) {
    ros::WallDuration(0.05).sleep();
    ros::spinOnce();
    std::lock_guard<std::mutex> lock(mutex);
    reported = loop_message.find("reconfigure rejected: update_rate_hz = 1.5") != std::string::npos;
  }
  EXPECT_TRUE(reported) << loop_message;
  EXPECT_EQ(loop_rate, "50.000");
  EXPECT_EQ(setRate(25.0), 25.0);
  EXPECT_EQ(setRate(50.0), 50.0);
}

/// Drives /clock for the sim-time tests: from 100 s, about real time (10 ms of sim time per 10 ms wall), with the
/// harness's inputs published every step. t_s may be set to jump the clock.
struct SimClock {
  explicit SimClock(Harness* harness)
      : h(harness), clock(ros::NodeHandle().advertise<rosgraph_msgs::Clock>("/clock", 10)) {}
  /// Advances the clock by dt_s [s] and publishes it.
  void tick(double dt_s) {
    t_s += dt_s;
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(t_s);
    clock.publish(c);
  }
  /// Steps until pred holds (true) or timeout_s of wall time passed (false).
  bool runUntil(const std::function<bool()>& pred, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      tick(0.01);
      h->publish();
      ros::WallDuration(0.01).sleep();
      ros::spinOnce();
      if (pred()) return true;
    }
    return false;
  }
  Harness* h;
  ros::Publisher clock;
  double t_s = 100.0;
};

// ---------------------------------------------------------------------------------------------------------
// Time jump (time_jump.test: use_sim_time, this test drives /clock).
TEST(TimeJump, BackwardJumpKeepsTheAccumulatedLoss) {
  Harness h("a");
  SimClock sim(&h);
  auto run = [&](const std::function<bool()>& pred, double timeout_s) { return sim.runUntil(pred, timeout_s); };
  ASSERT_TRUE(run([&] { return h.last().accumulated_loss_kg > 0.0 && h.count() > 50; }, 15.0));
  const double before = h.last().accumulated_loss_kg;
  const double distance_before = h.last().distance_m;
  // A looping bag: the clock restarts at 10 s. Under sim time the wheel steps on its inputs (here stamped on
  // arrival) and /wear samples it at the update rate, so the jump is awaited in the diagnostics' count.
  sim.t_s = 10.0;
  ASSERT_TRUE(run(
      [&] { return !h.diag("time jumps backward").empty() && std::stoi(h.diag("time jumps backward")) >= 1; }, 5.0));
  EXPECT_GE(h.last().accumulated_loss_kg, before);
  // Nothing absurd was integrated: the loss may only grow at the model's rate (W_r per metre at <= 0.5 m/s).
  EXPECT_LT(h.last().distance_m - distance_before, 0.5 * 1.0);
  ASSERT_TRUE(run([&] { return h.last().status == tread_wear::WheelWear::STATUS_OK &&
                               h.last().accumulated_loss_kg > before; }, 5.0));
  // Loss per distance is still W_r: the jump did not corrupt the integral.
  const WearResult direct = directResult();
  EXPECT_NEAR(h.last().accumulated_loss_kg / h.last().distance_m, direct.wear_rate_kg_per_m,
              1e-9 * direct.wear_rate_kg_per_m);
}

// ---------------------------------------------------------------------------------------------------------
// Time lost between two diagnostic reports (unintegrated_time.test: use_sim_time, this test drives /clock and
// publishes unstamped inputs, which the node stamps on arrival; its stale_timeout_s is 0.3 s, max_step_s 0.6 s).
// The report after the gap finds fresh inputs at its own instant, so only a level that covers the whole interval
// since the previous report can show the loss.
TEST(UnintegratedTime, AGapBetweenTwoReportsIsWarnWithItsSeconds) {
  Harness h("a");
  SimClock sim(&h);
  auto run = [&](const std::function<bool()>& pred, double timeout_s) { return sim.runUntil(pred, timeout_s); };
  // Steady state: a report with nothing lost (the start, before the first input, is in an earlier one).
  ASSERT_TRUE(run(
      [&] {
        int level = -1;
        h.diag("status", &level);
        return level == diagnostic_msgs::DiagnosticStatus::OK;
      },
      15.0));
  // Just after that report: 0.5 s of sim time without the speed (load and slip go on, so the wheel's input time
  // advances), in 10 ms ticks slow enough for the 50 Hz loop to step in between: the speed turns stale after 0.3 s.
  const int reports = h.diagCount();
  for (int k = 0; k < 50; ++k) {
    sim.tick(0.01);
    h.publish(kLoad, kSpeed, false);
    ros::WallDuration(0.005).sleep();
  }
  ASSERT_TRUE(run([&] { return h.diagCount() > reports; }, 5.0));
  int level = -1;
  EXPECT_EQ(h.diag("status", &level), "ok") << "the report must fall after the gap for this test to mean anything";
  EXPECT_EQ(level, diagnostic_msgs::DiagnosticStatus::WARN) << h.diagMessage();
  EXPECT_GT(std::stod(h.diag("unintegrated since last report: stale_input [s]")), 0.1) << h.diagMessage();
  EXPECT_NE(h.diagMessage().find("stale_input"), std::string::npos) << h.diagMessage();
  std::string vehicle_message;
  EXPECT_EQ(h.vehicleLevel(&vehicle_message), diagnostic_msgs::DiagnosticStatus::WARN) << vehicle_message;
  EXPECT_NE(vehicle_message.find("loss incomplete"), std::string::npos) << vehicle_message;
}

// ---------------------------------------------------------------------------------------------------------
// Fast replay (fast_replay.test): replay.launch plays a 300 s drive bag at rate 50 with its default clock rate;
// the node's loss per wheel must equal the offline replay's on the same bag (tread_wear_replay, run at build time)
// within 0.5 %, and nearly all the drive must be integrated (the offline replay's completeness bound, 1 %).
TEST(FastReplay, LossEqualsTheOfflineReplay) {
  ros::NodeHandle nh, pnh("~");
  std::string summary_path;
  ASSERT_TRUE(pnh.getParam("offline_summary", summary_path));
  std::ifstream in(summary_path);
  ASSERT_TRUE(in) << summary_path;
  const nlohmann::json offline = nlohmann::json::parse(in);
  ASSERT_TRUE(offline.at("complete").get<bool>());
  const double end_s = offline.at("end_s").get<double>();
  const double duration_s = offline.at("duration_s").get<double>();
  std::mutex mutex;
  tread_wear::VehicleWear last;
  ros::Subscriber sub =
      nh.subscribe<tread_wear::VehicleWear>("wear", 100, [&](const tread_wear::VehicleWear::ConstPtr& m) {
        std::lock_guard<std::mutex> l(mutex);
        last = *m;
      });
  // The wheels' last reports, to tell what a failure lost its time to.
  std::map<std::string, std::string> reports;
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> l(mutex);
        for (const auto& st : m->status) {
          const std::string::size_type at = st.name.find("wheel ");
          if (at == std::string::npos) continue;
          std::string text;
          for (const auto& kv : st.values)
            if (kv.key == "stale steps" || kv.key.rfind("time jumps", 0) == 0 || kv.key == "unaccounted time [s]")
              text += kv.key + " " + kv.value + "; ";
          reports[st.name.substr(at + 6)] = text;
        }
      });
  auto lastStamp_s = [&] {
    std::lock_guard<std::mutex> l(mutex);
    return last.header.stamp.toSec();
  };
  // Until the node has stepped at the bag's last clock tick (a clock step before its end), then a second more. The
  // player waits for the node (rate control), so on a loaded machine the replay runs slower than asked, not lossy.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(150.0);
  while (lastStamp_s() < end_s - 0.5 && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.01).sleep();
    ros::spinOnce();
  }
  ASSERT_GE(lastStamp_s(), end_s - 0.5) << "the replay did not reach the end of the bag in 150 s";
  // The node may still be working through queued inputs (it steps on them, not on the clock, and publishes on wall
  // time): until its losses stay the same for a second.
  auto losses = [&] {
    std::lock_guard<std::mutex> l(mutex);
    std::vector<double> kg;
    for (const auto& wheel : last.wheels) kg.push_back(wheel.accumulated_loss_kg);
    return kg;
  };
  std::vector<double> before = losses();
  for (int settled = 0; settled < 4 && ros::WallTime::now() < deadline;) {
    for (int k = 0; k < 25; ++k) {
      ros::WallDuration(0.01).sleep();
      ros::spinOnce();
    }
    const std::vector<double> now = losses();
    settled = now == before ? settled + 1 : 0;
    before = now;
  }
  std::lock_guard<std::mutex> l(mutex);
  const nlohmann::json& wheels = offline.at("wheels");
  ASSERT_EQ(last.wheels.size(), wheels.size());
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    const tread_wear::WheelWear& live = last.wheels[i];
    ASSERT_EQ(live.wheel, wheels[i].at("name").get<std::string>());
    const double reference_kg = wheels[i].at("mass_loss_kg").get<double>();
    ASSERT_GT(reference_kg, 0.0);
    EXPECT_NEAR(live.accumulated_loss_kg, reference_kg, 0.005 * reference_kg)
        << live.wheel << ": live/offline - 1 = " << live.accumulated_loss_kg / reference_kg - 1.0 << "; "
        << reports[live.wheel];
    EXPECT_LT(live.unaccounted_time_s, 0.01 * duration_s) << live.wheel << ": " << reports[live.wheel];
    std::printf("fast replay %s: live %.6g kg, offline %.6g kg (%+.3f %%), unaccounted %.3f s\n", live.wheel.c_str(),
                live.accumulated_loss_kg, reference_kg, 100.0 * (live.accumulated_loss_kg / reference_kg - 1.0),
                live.unaccounted_time_s);
  }
}

// ---------------------------------------------------------------------------------------------------------
// kill -9 and restart (persistence.test): this test starts the node binary itself against the rostest master.
class NodeProcess {
 public:
  explicit NodeProcess(const std::string& name) {
    pid_ = fork();
    if (pid_ == 0) {
      const std::string name_arg = "__name:=" + name;
      execl(TREAD_WEAR_NODE_BINARY, TREAD_WEAR_NODE_BINARY, name_arg.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~NodeProcess() { kill(SIGKILL); }
  void kill(int sig) {
    if (pid_ <= 0) return;
    ::kill(pid_, sig);
    int status;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

TEST(Persistence, KillNineLosesAtMostOneSaveInterval) {
  const std::string state_file = "/tmp/tread_wear_persist_" + std::to_string(getpid()) + ".json";
  std::remove(state_file.c_str());
  const double save_interval_s = 0.5;
  ros::NodeHandle nh;
  XmlRpc::XmlRpcValue wheels;
  wheels[0]["name"] = "a";
  wheels[0]["tire_params"] = kTireFile;
  wheels[0]["tire_id"] = "tire-a";
  ros::param::set("/persist_node/wheels", wheels);
  ros::param::set("/persist_node/preset", "fast");
  ros::param::set("/persist_node/update_rate_hz", 50.0);
  ros::param::set("/persist_node/marker_rate_hz", 0.0);
  ros::param::set("/persist_node/state_file", state_file);
  ros::param::set("/persist_node/save_interval_s", save_interval_s);

  Harness h("a");
  double loss_at_kill = 0.0, rate_kg_per_s = 0.0;
  {
    NodeProcess node("persist_node");
    ASSERT_TRUE(h.waitForNode(15.0));
    ASSERT_TRUE(h.spinUntil([&] { return h.last().distance_m > 0.5; }, 10.0));
    loss_at_kill = h.last().accumulated_loss_kg;
    rate_kg_per_s = h.last().wear_rate_kg_per_s;
    node.kill(SIGKILL);
  }
  const LoadResult saved = StateStore(state_file).load();
  ASSERT_EQ(saved.status, LoadStatus::kLoaded) << saved.message;
  const WheelRecord* rec = saved.state.find("a");
  ASSERT_NE(rec, nullptr);
  // Lost = accumulation since the last save: at most one save interval of wear, plus one update period
  // and one message transit (0.1 s margin) because loss_at_kill was read a little before the kill.
  const double max_lost = rate_kg_per_s * (save_interval_s + 0.1);
  EXPECT_LE(loss_at_kill - rec->accumulated_loss_kg, max_lost);
  EXPECT_GT(rec->accumulated_loss_kg, 0.0);
  EXPECT_EQ(rec->tire_id, "tire-a");

  // Restart: the first output continues from the saved value.
  const int before = h.count();
  NodeProcess node("persist_node");
  ASSERT_TRUE(h.spinUntil([&] { return h.count() > before; }, 15.0, false));
  EXPECT_EQ(h.last().accumulated_loss_kg, rec->accumulated_loss_kg);
  ASSERT_TRUE(h.spinUntil([&] { return h.last().accumulated_loss_kg > rec->accumulated_loss_kg; }, 10.0));
  node.kill(SIGINT);  // clean shutdown saves
  const LoadResult final_state = StateStore(state_file).load();
  ASSERT_EQ(final_state.status, LoadStatus::kLoaded);
  EXPECT_GT(final_state.state.find("a")->accumulated_loss_kg, rec->accumulated_loss_kg);
  std::remove(state_file.c_str());
}

TEST(Persistence, CorruptStateFileIsMovedAsideAndReported) {
  const std::string state_file = "/tmp/tread_wear_corrupt_" + std::to_string(getpid()) + ".json";
  std::ofstream(state_file) << "{\"format\": \"tread_wear_state\", \"version\": 1, \"wheels\": [";
  ros::param::set("/corrupt_node/state_file", state_file);
  XmlRpc::XmlRpcValue wheels;
  wheels[0]["name"] = "c";
  wheels[0]["tire_params"] = kTireFile;
  ros::param::set("/corrupt_node/wheels", wheels);
  ros::param::set("/corrupt_node/preset", "fast");
  ros::NodeHandle nh;
  std::string persistence_level_message;
  int persistence_level = -1;
  ros::Subscriber ds = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        for (const auto& s : m->status)
          if (s.name.find("persistence") != std::string::npos) {
            persistence_level = s.level;
            persistence_level_message = s.message;
          }
      });
  NodeProcess node("corrupt_node");
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(15.0);
  while (persistence_level < 0 && ros::WallTime::now() < end) {
    ros::WallDuration(0.05).sleep();
    ros::spinOnce();
  }
  EXPECT_EQ(persistence_level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(persistence_level_message.find("corrupt"), std::string::npos) << persistence_level_message;
  EXPECT_NE(persistence_level_message.find(".corrupt-"), std::string::npos) << persistence_level_message;
  node.kill(SIGINT);
  std::remove(state_file.c_str());
}

// ---------------------------------------------------------------------------------------------------------
// Bag regressions (bag.test): the test writes a bag of one wheel's inputs, plays it with --clock through the node
// (use_sim_time) and compares the final accumulated loss with an independent integration of the core model.

/// Wheel a's inputs at time t [s] from the start of a drive.
using DriveInputs = std::function<OperatingPoint(double t_s)>;

constexpr double kBagRateHz = 50.0;

/// Writes duration_s of one wheel's inputs at kBagRateHz from bag time start_s, plays the bag through the running
/// node and returns the wheel's last output. Each test uses its own wheel and a later start time, so that the
/// node's state from an earlier test does not enter.
tread_wear::WheelWear playThroughNode(const std::string& wheel, double start_s, const DriveInputs& inputs,
                                      double duration_s, int* outputs_received) {
  const std::string bag_path = "/tmp/tread_wear_regression_" + std::to_string(getpid()) + ".bag";
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    const int n = static_cast<int>(std::lround(duration_s * kBagRateHz));
    for (int k = 0; k <= n; ++k) {
      const OperatingPoint op = inputs(k / kBagRateHz);
      const ros::Time t(start_s + k / kBagRateHz);
      tread_wear::WheelLoad l;
      l.header.stamp = t;
      l.load_n = op.load_n;
      tread_wear::WheelSlip s;
      s.header.stamp = t;
      s.slip_angle_rad = op.slip_angle_rad;
      s.slip_ratio = op.slip_ratio;
      s.path_curvature_per_m = op.path_curvature_per_m;
      tread_wear::WheelSpeed v;
      v.header.stamp = t;
      v.speed_mps = op.speed_mps;
      bag.write("/wheels/" + wheel + "/load", t, l);
      bag.write("/wheels/" + wheel + "/slip", t, s);
      bag.write("/wheels/" + wheel + "/speed", t, v);
    }
  }
  Harness h(wheel);
  // The node has no time yet (sim time 0): wait until it subscribed, then play.
  ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::WallTime::now() < end) {
    ros::WallDuration(0.1).sleep();
    ros::spinOnce();
    std::vector<std::string> nodes;
    if (ros::master::getNodes(nodes) &&
        std::find(nodes.begin(), nodes.end(), "/tread_wear_node") != nodes.end())
      break;
  }
  const pid_t player = fork();
  if (player == 0) {
    execl("/usr/lib/rosbag/play", "play", "--clock", "-q", "-d", "1", bag_path.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(player, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";
  ros::WallDuration(0.3).sleep();
  ros::spinOnce();
  std::remove(bag_path.c_str());
  *outputs_received = h.count();
  return h.last();
}

// Integrated time: from the first update step with all three inputs to the last step before the clock stops.
// Each end can lose at most one update period (50 Hz -> 0.02 s) plus one clock tick of rosbag play (100 Hz ->
// 0.01 s).
constexpr double kEndLossS = 1.0 / 50.0 + 1.0 / 100.0;

TEST(BagRegression, ConstantDriveMatchesWrTimesDistance) {
  const double duration_s = 6.0;
  const DriveInputs constant = [](double) { return rigPoint(); };
  int received = 0;
  const double start_s = 1000.0;
  const tread_wear::WheelWear m = playThroughNode("a", start_s, constant, duration_s, &received);
  const WearResult direct = directResult();
  ASSERT_GT(received, 0);
  // |error| <= 2 x 0.03 s = 0.06 s of the 6 s drive = 1%.
  const double expected = direct.wear_rate_kg_per_m * kSpeed * duration_s;
  const double tolerance = direct.wear_rate_kg_per_m * kSpeed * 2.0 * kEndLossS;
  EXPECT_NEAR(m.accumulated_loss_kg, expected, tolerance) << "relative error "
                                                          << (m.accumulated_loss_kg - expected) / expected;
  EXPECT_NEAR(m.distance_m, kSpeed * duration_s, kSpeed * 2.0 * kEndLossS);
  EXPECT_NEAR(m.accumulated_loss_kg / m.distance_m, direct.wear_rate_kg_per_m, 1e-9 * direct.wear_rate_kg_per_m);
  EXPECT_EQ(m.header.stamp.toSec() > start_s, true);  // outputs are stamped with the bag's (simulated) time
}

// A drive whose speed, slip angle and load all vary: the node's loss equals the core model evaluated at every
// input sample and integrated by the trapezoid rule (what tread_wear_replay is tested to do, test_drive_replay),
// so the live node and the offline replay agree on the same bag.
TEST(BagRegression, VaryingDriveMatchesTheModelIntegratedAlongIt) {
  const double duration_s = 6.0;
  const DriveInputs varying = [](double t) {
    OperatingPoint op;
    op.load_n = kLoad * (1.0 + 0.2 * std::sin(2.0 * units::kPi * t / 4.0));
    op.speed_mps = 0.5 + t / 6.0;                                                 // 0.5 -> 1.5 m/s
    op.slip_angle_rad = (-2.0 + 1.5 * std::sin(2.0 * units::kPi * t / 3.0)) * units::kDegree;
    op.path_curvature_per_m = kCurvature;
    return op;
  };
  int received = 0;
  const tread_wear::WheelWear m = playThroughNode("b", 2000.0, varying, duration_s, &received);
  ASSERT_GT(received, 0);

  WearModelOptions options;
  options.preset = Preset::kFast;  // two_wheels.yaml
  const WearModel model(loadTireParams(kTireFile), options);
  double expected = 0.0, distance = 0.0, prev_rate = 0.0, prev_speed = 0.0, max_rate = 0.0;
  const int n = static_cast<int>(std::lround(duration_s * kBagRateHz));
  for (int k = 0; k <= n; ++k) {
    const OperatingPoint op = varying(k / kBagRateHz);
    WearResult r;
    model.evaluate(op, &r);
    if (k > 0) {
      expected += 0.5 * (prev_rate + r.wear_rate_kg_per_s) / kBagRateHz;
      distance += 0.5 * (prev_speed + op.speed_mps) / kBagRateHz;
    }
    prev_rate = r.wear_rate_kg_per_s;
    prev_speed = op.speed_mps;
    max_rate = std::max(max_rate, r.wear_rate_kg_per_s);
  }
  // Both ends as above, plus the node timer's phase against the samples: it may hold each sample up to one
  // update period (0.02 s), which shifts the integrand by at most that: |error| <= max rate x (2 x 0.03 + 0.02) s.
  const double tolerance = max_rate * (2.0 * kEndLossS + 1.0 / 50.0);
  EXPECT_NEAR(m.accumulated_loss_kg, expected, tolerance) << "relative error "
                                                          << (m.accumulated_loss_kg - expected) / expected;
  EXPECT_NEAR(m.distance_m, distance, 1.5 * (2.0 * kEndLossS + 1.0 / 50.0));
  EXPECT_LT(tolerance / expected, 0.03) << "the check must stay sharper than the variation it tests";
  RecordProperty("relative_error", std::to_string((m.accumulated_loss_kg - expected) / expected));
  RecordProperty("relative_tolerance", std::to_string(tolerance / expected));
}

}  // namespace
}  // namespace tread_wear

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tread_wear_node");
  ros::NodeHandle nh;  // keeps the node alive for the whole run
  return RUN_ALL_TESTS();
}
