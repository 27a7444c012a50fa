// vehicle_inputs_node through a running ROS graph (test/ros/vehicle_inputs.test, vehicle_inputs_no_tf.test):
// synthetic IMU / JointState / Odometry of a known steady state in, wheels/<name>/{load,slip,speed,input_quality}
// and /diagnostics out. The IMU is mounted turned by 90 degrees about z (tf base_link -> imu_link), so a node that
// did not rotate the IMU into base_link would see the lateral specific force as longitudinal.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosgraph_msgs/Clock.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "tread_wear/WheelInputQuality.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/rolling_radius_store.h"

namespace {

constexpr int kWheels = 4;
const std::array<std::string, kWheels> kNames{{"front_left", "front_right", "rear_left", "rear_right"}};
const std::array<std::string, kWheels> kJoints{
    {"wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint", "wheel_rear_right_joint"}};
// config/vehicle_passenger_car.yaml
constexpr double kMass = 1450.0, kL = 2.64, kLf = 1.06, kH = 0.55, kTf = 1.55, kTr = 1.52, kLambdaF = 0.6;
constexpr double kG = 9.81, kRadius = 0.31, kSteeringRatio = 15.0;

struct WheelSeen {
  int loads = 0;
  double load_sum = 0.0, slip_ratio_sum = 0.0, slip_angle_sum = 0.0, speed_sum = 0.0;
  int slips = 0, speeds = 0;
  tread_wear::WheelInputQuality quality;
  int qualities = 0;
};

struct Drive {
  double speed_mps = 15.0;
  double yaw_rate_rps = 0.0;       // > 0 left
  bool imu = true;                 // publish the IMU
  bool imu_nan = false;            // NaN in the specific force
  bool joint_out_of_order = false; // every other JointState stamped 50 ms in the past
  int omit_wheel = -1;             // this wheel's joint left out of the JointState messages
};

class Harness {
 public:
  Harness() {
    imu_pub_ = nh_.advertise<sensor_msgs::Imu>("imu", 50);
    joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 50);
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odom", 50);
    for (int i = 0; i < kWheels; ++i) {
      const std::string p = "wheels/" + kNames[i] + "/";
      subs_.push_back(nh_.subscribe<tread_wear::WheelLoad>(p + "load", 100, [this, i](const auto& m) {
        std::lock_guard<std::mutex> l(mutex_);
        seen_[i].load_sum += m->load_n;
        ++seen_[i].loads;
      }));
      subs_.push_back(nh_.subscribe<tread_wear::WheelSlip>(p + "slip", 100, [this, i](const auto& m) {
        std::lock_guard<std::mutex> l(mutex_);
        seen_[i].slip_ratio_sum += m->slip_ratio;
        seen_[i].slip_angle_sum += m->slip_angle_rad;
        ++seen_[i].slips;
      }));
      subs_.push_back(nh_.subscribe<tread_wear::WheelSpeed>(p + "speed", 100, [this, i](const auto& m) {
        std::lock_guard<std::mutex> l(mutex_);
        seen_[i].speed_sum += m->speed_mps;
        ++seen_[i].speeds;
      }));
      subs_.push_back(nh_.subscribe<tread_wear::WheelInputQuality>(p + "input_quality", 100, [this, i](const auto& m) {
        std::lock_guard<std::mutex> l(mutex_);
        seen_[i].quality = *m;
        ++seen_[i].qualities;
      }));
    }
    subs_.push_back(nh_.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex_);
      for (const auto& s : m->status) diagnostics_[s.name] = s;
    }));
  }

  void publishTf() {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "base_link";
    t.child_frame_id = "imu_link";
    t.transform.translation.z = kH;  // at the CoG: no lever arm
    t.transform.rotation.z = std::sin(M_PI / 4.0);  // yaw +90 deg: IMU x = base y, IMU y = -base x
    t.transform.rotation.w = std::cos(M_PI / 4.0);
    tf_.sendTransform(t);
  }

  void waitForNode() {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while (ros::ok() && ros::WallTime::now() < end &&
           (imu_pub_.getNumSubscribers() == 0 || joint_pub_.getNumSubscribers() == 0 ||
            odom_pub_.getNumSubscribers() == 0))
      ros::WallDuration(0.02).sleep();
  }

  // Publishes the drive at 100 Hz for duration_s; clears what was seen after settle_s.
  void drive(const Drive& d, double duration_s, double settle_s) {
    const ros::WallTime start = ros::WallTime::now();
    bool cleared = false;
    int k = 0;
    ros::Rate rate(100.0);
    while (ros::ok() && (ros::WallTime::now() - start).toSec() < duration_s) {
      if (!cleared && (ros::WallTime::now() - start).toSec() >= settle_s) {
        clear();
        cleared = true;
      }
      publishSample(d, k++);
      rate.sleep();
    }
  }

  void publishSample(const Drive& d, int k) { publishSample(d, k, ros::Time::now()); }
  void publishSample(const Drive& d, int k, const ros::Time& now) {
    const double v = d.speed_mps, r = d.yaw_rate_rps, ay = v * r;
    if (d.imu) {
      sensor_msgs::Imu imu;
      imu.header.stamp = now;
      imu.header.frame_id = "imu_link";
      // base f = (0, ay, g), w = (0, 0, r); IMU axes: x_imu = y_base, y_imu = -x_base
      imu.linear_acceleration.x = d.imu_nan ? std::nan("") : ay;
      imu.linear_acceleration.y = 0.0;
      imu.linear_acceleration.z = kG;
      imu.angular_velocity.z = r;
      imu.orientation_covariance[0] = -1.0;
      imu_pub_.publish(imu);
    }
    sensor_msgs::JointState js;
    js.header.stamp = (d.joint_out_of_order && k % 2 == 1) ? now - ros::Duration(0.05) : now;
    const double lr = kL - kLf;
    const std::array<double, kWheels> x{{kLf, kLf, -lr, -lr}}, y{{kTf / 2, -kTf / 2, kTr / 2, -kTr / 2}};
    const double k_path = v > 0.0 ? r / v : 0.0;
    const double delta = std::atan(kL * k_path);
    for (int i = 0; i < kWheels; ++i) {
      if (i == d.omit_wheel) continue;
      js.name.push_back(kJoints[i]);
      js.velocity.push_back(std::hypot(v - r * y[i], r * x[i]) / kRadius);
      js.position.push_back(0.0);
    }
    js.name.push_back("steering_wheel_joint");
    js.position.push_back(kSteeringRatio * delta);
    js.velocity.push_back(0.0);
    joint_pub_.publish(js);
    nav_msgs::Odometry odom;
    odom.header.stamp = now;
    odom.header.frame_id = "odom";
    odom.child_frame_id = "base_link";
    odom.twist.twist.linear.x = v;
    odom_pub_.publish(odom);
  }

  void clear() {
    std::lock_guard<std::mutex> l(mutex_);
    seen_ = {};
  }
  WheelSeen seen(int i) {
    std::lock_guard<std::mutex> l(mutex_);
    return seen_[i];
  }
  bool diagnostic(const std::string& name, diagnostic_msgs::DiagnosticStatus* out) {
    std::lock_guard<std::mutex> l(mutex_);
    auto it = diagnostics_.find(name);
    if (it == diagnostics_.end()) return false;
    *out = it->second;
    return true;
  }
  void clearDiagnostics() {
    std::lock_guard<std::mutex> l(mutex_);
    diagnostics_.clear();
  }
  static std::string value(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
    for (const auto& kv : s.values)
      if (kv.key == key) return kv.value;
    return "";
  }

 private:
  ros::NodeHandle nh_;
  ros::Publisher imu_pub_, joint_pub_, odom_pub_;
  std::vector<ros::Subscriber> subs_;
  tf2_ros::StaticTransformBroadcaster tf_;
  std::mutex mutex_;
  std::array<WheelSeen, kWheels> seen_{};
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> diagnostics_;
};

std::unique_ptr<Harness> harness;

double staticLoad(int i) {
  const double lr = kL - kLf;
  return kMass * kG * (i < 2 ? lr : kLf) / kL / 2.0;
}

TEST(VehicleInputs, SteadyStraightGivesStaticLoadsAndNoSlip) {
  harness->drive(Drive{}, 1.5, 1.0);
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen s = harness->seen(i);
    ASSERT_GT(s.loads, 20) << kNames[i];  // 100 Hz over 0.5 s
    ASSERT_GT(s.slips, 20) << kNames[i];
    ASSERT_GT(s.speeds, 20) << kNames[i];
    const double load = s.load_sum / s.loads;
    EXPECT_NEAR(load, staticLoad(i), 0.02 * staticLoad(i)) << kNames[i];
    EXPECT_NEAR(s.slip_ratio_sum / s.slips, 0.0, 0.005) << kNames[i];
    EXPECT_NEAR(s.slip_angle_sum / s.slips, 0.0, 0.002) << kNames[i];
    EXPECT_NEAR(s.speed_sum / s.speeds, 15.0, 0.15) << kNames[i];
    EXPECT_EQ(s.quality.wheel, kNames[i]);
    EXPECT_TRUE(s.quality.published);
    EXPECT_EQ(s.quality.flags & tread_wear::WheelInputQuality::FLAG_NO_IMU, 0u);
  }
}

TEST(VehicleInputs, SteadyLeftTurnLoadsTheOuterWheels) {
  Drive d;
  d.yaw_rate_rps = 0.15;  // R = 100 m at 15 m/s: a_y = 2.25 m/s^2
  harness->drive(d, 2.0, 1.5);
  std::array<double, kWheels> load{};
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen s = harness->seen(i);
    ASSERT_GT(s.loads, 20) << kNames[i];
    load[i] = s.load_sum / s.loads;
  }
  const double ay = 15.0 * 0.15;
  const double d_front = kMass * ay * kH * kLambdaF / kTf, d_rear = kMass * ay * kH * (1.0 - kLambdaF) / kTr;
  EXPECT_GT(load[1], load[0]);
  EXPECT_GT(load[3], load[2]);
  EXPECT_NEAR(load[1] - load[0], 2.0 * d_front, 0.1 * 2.0 * d_front);
  EXPECT_NEAR(load[3] - load[2], 2.0 * d_rear, 0.1 * 2.0 * d_rear);
  for (int i = 0; i < kWheels; ++i) EXPECT_NEAR(load[i], staticLoad(i) + (i % 2 ? 1 : -1) * (i < 2 ? d_front : d_rear),
                                                0.03 * staticLoad(i)) << kNames[i];
}

TEST(VehicleInputs, NanImuAndOutOfOrderStampsAreRejectedAndReported) {
  Drive bad;
  bad.imu_nan = true;
  bad.joint_out_of_order = true;
  harness->clearDiagnostics();
  harness->drive(bad, 0.3, 0.0);
  harness->drive(Drive{}, 0.6, 0.1);  // recovers; the diagnostics (0.25 s period) report the rejections
  diagnostic_msgs::DiagnosticStatus s;
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: sensors", &s));
  EXPECT_GE(std::stoi(Harness::value(s, "imu not_finite")), 20);
  EXPECT_GE(std::stoi(Harness::value(s, "wheel_speed out_of_order")), 10);
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen w = harness->seen(i);
    EXPECT_GT(w.loads, 20) << kNames[i];
    EXPECT_NEAR(w.load_sum / w.loads, staticLoad(i), 0.02 * staticLoad(i)) << kNames[i];
  }
}

TEST(VehicleInputs, AWheelWithoutSpeedIsPublishedWithItsSlipRatioFromTheForceDemandAndItsQualitySaysSo) {
  Drive d;
  d.omit_wheel = 3;  // rear_right
  harness->drive(d, 0.8, 0.4);
  const WheelSeen rr = harness->seen(3);
  ASSERT_GT(rr.loads, 20);
  ASSERT_GT(rr.slips, 20);
  EXPECT_GT(rr.speeds, 20);
  EXPECT_TRUE(rr.quality.published);
  EXPECT_NE(rr.quality.flags & tread_wear::WheelInputQuality::FLAG_WHEEL_SPEED_MISSING, 0u);
  EXPECT_NE(rr.quality.flags & tread_wear::WheelInputQuality::FLAG_SLIP_RATIO_FROM_FORCE, 0u);
  EXPECT_EQ(rr.quality.slip_ratio_quality, tread_wear::WheelInputQuality::QUALITY_DEGRADED);
  // Steady straight: the force demand is the resistances alone, a slip ratio well below 0.005 (an undriven rear
  // wheel rolls against its own rolling resistance only).
  EXPECT_NEAR(rr.slip_ratio_sum / rr.slips, 0.0, 0.005);
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen w = harness->seen(i);
    ASSERT_GT(w.loads, 20) << kNames[i];
    EXPECT_NEAR(w.load_sum / w.loads, staticLoad(i), 0.02 * staticLoad(i)) << kNames[i];
  }
  diagnostic_msgs::DiagnosticStatus s;
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: wheel rear_right", &s));
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(s.message.find("wheel speed missing"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("slip ratio from the force demand"), std::string::npos) << s.message;
  harness->drive(Drive{}, 0.5, 0.3);  // back
  EXPECT_GT(harness->seen(3).loads, 10);
  EXPECT_EQ(harness->seen(3).quality.flags & tread_wear::WheelInputQuality::FLAG_SLIP_RATIO_FROM_FORCE, 0u);
}

TEST(VehicleInputs, ImuStopsDegradesToTheFallbackWithADiagnostic) {
  Drive no_imu;
  no_imu.imu = false;
  harness->clearDiagnostics();
  harness->drive(no_imu, 1.0, 0.4);
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen w = harness->seen(i);
    ASSERT_GT(w.loads, 20) << kNames[i];  // still published, from the fallback, never a silent zero
    EXPECT_NEAR(w.load_sum / w.loads, staticLoad(i), 0.03 * staticLoad(i)) << kNames[i];
    EXPECT_NE(w.quality.flags & tread_wear::WheelInputQuality::FLAG_NO_IMU, 0u) << kNames[i];
    EXPECT_EQ(w.quality.load_quality, tread_wear::WheelInputQuality::QUALITY_DEGRADED) << kNames[i];
    EXPECT_EQ(w.quality.accel_source, 2) << kNames[i];  // speed derivative
  }
  diagnostic_msgs::DiagnosticStatus s;
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: sensors", &s));
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(s.message.find("imu missing or stale"), std::string::npos) << s.message;
  EXPECT_EQ(Harness::value(s, "acceleration source"), "speed_derivative");
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: publish cycle", &s));
  EXPECT_GT(std::stoi(Harness::value(s, "cycles")), 100);
  EXPECT_FALSE(Harness::value(s, "max cycle CPU [us]").empty());
}

TEST(VehicleInputsTimeJump, AfterTheClockJumpsBackTheEstimatorRestartsAndPublishesAgain) {
  // Simulated time driven by the test (use_sim_time): 1.5 s from t = 100 s, then back to t = 10 s for 1.5 s.
  ros::NodeHandle nh;
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  const ros::WallTime wait_end = ros::WallTime::now() + ros::WallDuration(5.0);
  while (clock.getNumSubscribers() == 0 && ros::WallTime::now() < wait_end) ros::WallDuration(0.02).sleep();
  auto run = [&](double t0, int steps) {
    for (int k = 0; k < steps && ros::ok(); ++k) {
      rosgraph_msgs::Clock c;
      c.clock = ros::Time(t0 + 0.01 * k);
      clock.publish(c);
      harness->publishSample(Drive{}, k, c.clock);
      ros::WallDuration(0.01).sleep();
    }
  };
  harness->clearDiagnostics();
  run(100.0, 150);
  harness->clear();
  run(10.0, 150);
  diagnostic_msgs::DiagnosticStatus s;
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: publish cycle", &s));
  EXPECT_GE(std::stoi(Harness::value(s, "clock faults")), 1);
  EXPECT_GE(std::stoi(Harness::value(s, "estimator restarts")), 1);
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen w = harness->seen(i);
    ASSERT_GT(w.loads, 50) << kNames[i];  // publishing again after the jump, at the right loads
    EXPECT_NEAR(w.load_sum / w.loads, staticLoad(i), 0.02 * staticLoad(i)) << kNames[i];
  }
}

TEST(VehicleInputsNoTf, MissingImuTransformIsADiagnosticAndTheImuIsNotUsed) {
  harness->clearDiagnostics();
  harness->drive(Drive{}, 1.2, 0.6);
  diagnostic_msgs::DiagnosticStatus s;
  ASSERT_TRUE(harness->diagnostic("vehicle_inputs_node: sensors", &s));
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(s.message.find("no transform"), std::string::npos) << s.message;
  EXPECT_EQ(Harness::value(s, "imu samples without tf"), Harness::value(s, "imu samples received"));
  EXPECT_EQ(Harness::value(s, "imu tf").rfind("missing", 0), 0u) << Harness::value(s, "imu tf");
  // The learned radii are saved (every save_interval_s = 0.5 s here) for the next start.
  std::string file;
  ASSERT_TRUE(ros::param::get("/radius_file_under_test", file));
  std::array<tread_wear::RollingRadiusState, kWheels> radii{};
  std::string error;
  EXPECT_EQ(tread_wear::loadRollingRadii(file, kNames, &radii, &error), tread_wear::RadiusLoadStatus::kLoaded) << error;
  for (const auto& r : radii) EXPECT_NEAR(r.radius_m, kRadius, 0.02);
  std::remove(file.c_str());
  for (int i = 0; i < kWheels; ++i) {
    const WheelSeen w = harness->seen(i);
    ASSERT_GT(w.loads, 20) << kNames[i] << " qualities " << w.qualities << " load " << int(w.quality.load_quality)
                           << " slip angle " << int(w.quality.slip_angle_quality) << " slip ratio "
                           << int(w.quality.slip_ratio_quality) << " flags " << w.quality.flags << " speed source "
                           << int(w.quality.speed_source) << " " << s.message;
    EXPECT_NE(w.quality.flags & tread_wear::WheelInputQuality::FLAG_NO_IMU, 0u) << kNames[i];
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_vehicle_inputs");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  harness = std::make_unique<Harness>();
  bool tf = true;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--no-tf") tf = false;
  if (tf) harness->publishTf();
  harness->waitForNode();
  const int rc = RUN_ALL_TESTS();
  harness.reset();
  return rc;
}
