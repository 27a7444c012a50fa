// The node and the tool are one front end (estimation/vehicle_input_pipeline.h): a sensor bag played with rosbag
// play --clock to vehicle_inputs_node in input time gives, at every stamp the node publishes, exactly the per-wheel
// inputs that tread_wear_vehicle_inputs wrote from the same bag with the same configuration file
// (test/ros/vehicle_inputs_bag.test). The test writes the bag (a 30 s drive with its sensors, as tread_wear_drive
// --sensors) and runs the tool on it in-process (runVehicleInputsCli with the shipped config/vehicle_inputs.yaml,
// the file the launch loads into the node).
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/ros/bag/vehicle_inputs_cli.h"
#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
constexpr int kWheels = 4;
const std::array<std::string, kWheels> kNames{{"front_left", "front_right", "rear_left", "rear_right"}};

/// One wheel's inputs at one stamp, as published or written.
struct Inputs {
  double load_n = 0.0, slip_angle_rad = 0.0, slip_ratio = 0.0, path_curvature_per_m = 0.0, speed_mps = 0.0;
  int parts = 0;  ///< load, slip and speed seen (3 when complete)
};
using InputsByStamp = std::array<std::map<ros::Time, Inputs>, kWheels>;

void addLoad(InputsByStamp* table, int w, const tread_wear::WheelLoad& m) {
  Inputs& in = (*table)[static_cast<std::size_t>(w)][m.header.stamp];
  in.load_n = m.load_n;
  ++in.parts;
}
void addSlip(InputsByStamp* table, int w, const tread_wear::WheelSlip& m) {
  Inputs& in = (*table)[static_cast<std::size_t>(w)][m.header.stamp];
  in.slip_angle_rad = m.slip_angle_rad;
  in.slip_ratio = m.slip_ratio;
  in.path_curvature_per_m = m.path_curvature_per_m;
  ++in.parts;
}
void addSpeed(InputsByStamp* table, int w, const tread_wear::WheelSpeed& m) {
  Inputs& in = (*table)[static_cast<std::size_t>(w)][m.header.stamp];
  in.speed_mps = m.speed_mps;
  ++in.parts;
}

InputsByStamp readToolBag(const std::string& path) {
  InputsByStamp table;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  for (int w = 0; w < kWheels; ++w) {
    const std::string prefix = "/wheels/" + kNames[static_cast<std::size_t>(w)] + "/";
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(prefix + "load")))
      if (const auto msg = m.instantiate<tread_wear::WheelLoad>()) addLoad(&table, w, *msg);
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(prefix + "slip")))
      if (const auto msg = m.instantiate<tread_wear::WheelSlip>()) addSlip(&table, w, *msg);
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(prefix + "speed")))
      if (const auto msg = m.instantiate<tread_wear::WheelSpeed>()) addSpeed(&table, w, *msg);
  }
  return table;
}

/// 30 s: standing, a launch to 16.7 m/s, cruising through a 2 m/s^2 left bend, braking to 8.3 m/s.
std::string writeSensorBag(const std::string& path) {
  using namespace tread_wear;
  const SpeedProfile profile{{0, 2, 10, 20, 25, 30}, {0, 0, 16.7, 16.7, 8.3, 8.3}, {}, "node_vs_tool"};
  const Route route{{{0.0, 80.0, 0.0, 0.0, -1},
                     {80.0, 30.0, 0.0, 2.0 / 279.0, -1},
                     {110.0, 80.0, 2.0 / 279.0, 2.0 / 279.0, -1},
                     {190.0, 30.0, 2.0 / 279.0, 0.0, -1},
                     {220.0, 1000.0, 0.0, 0.0, -1}},
                    {}};
  DriveOptions options;
  options.sensors = true;
  for (int w = 0; w < kWheelCount; ++w) options.wheel_names.push_back(wheelName(w));
  writeDriveBag(path, profile, route, VehicleModel(loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml")),
                RouteParams(), options);
  return path;
}

bool nodeSubscribed(const std::string& topic) {
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", request, response, payload, true)) return false;
  const XmlRpc::XmlRpcValue& subscribers = payload[1];
  for (int i = 0; i < subscribers.size(); ++i) {
    if (static_cast<std::string>(subscribers[i][0]) != topic) continue;
    for (int j = 0; j < subscribers[i][1].size(); ++j)
      if (static_cast<std::string>(subscribers[i][1][j]) == "/vehicle_inputs_node") return true;
  }
  return false;
}

TEST(VehicleInputsBagPlay, TheNodeGivesTheToolsPerWheelInputsOnTheSameBag) {
  ros::NodeHandle nh;
  const std::string dir = ::testing::TempDir();
  const std::string sensor_bag = writeSensorBag(dir + "vi_play_sensors.bag"), tool_bag = dir + "vi_play_tool.bag";
  // The shipped configuration with the largest delivery bound (the launch file sets the node's to the same): the
  // bag is played at 3x, so a delivery delay of 67 ms on a loaded machine is already 0.2 s of input time, the
  // shipped bound, past which a lagging stream is not waited for and the node's cycles may differ from the tool's.
  const std::string config = dir + "vi_play_inputs.yaml";
  {
    std::ifstream shipped(kSource + "/config/vehicle_inputs.yaml");
    std::ostringstream text;
    text << shipped.rdbuf();
    const std::string with_bound = std::regex_replace(text.str(), std::regex("\ninput_delay_s: [0-9.]+"),
                                                      "\ninput_delay_s: 1.0");
    ASSERT_NE(with_bound, text.str()) << "no input_delay_s in config/vehicle_inputs.yaml";
    std::ofstream(config) << with_bound;
  }
  std::vector<const char*> argv{"tread_wear_vehicle_inputs", sensor_bag.c_str(), tool_bag.c_str(), "--config",
                                config.c_str()};
  std::ostringstream out, err;
  ASSERT_EQ(tread_wear::runVehicleInputsCli(static_cast<int>(argv.size()), argv.data(), kSource, out, err), 0)
      << err.str();
  const InputsByStamp tool = readToolBag(tool_bag);
  ASSERT_EQ(tool[0].size(), 3001u);  // 30 s at 100 Hz, both ends

  std::mutex mutex;
  InputsByStamp node;
  std::size_t received = 0;  // messages from the node, under `mutex`
  std::vector<ros::Subscriber> subs;
  for (int w = 0; w < kWheels; ++w) {
    const std::string prefix = "wheels/" + kNames[static_cast<std::size_t>(w)] + "/";
    subs.push_back(nh.subscribe<tread_wear::WheelLoad>(prefix + "load", 10000, [&, w](const auto& m) {
      std::lock_guard<std::mutex> lock(mutex);
      addLoad(&node, w, *m);
      ++received;
    }));
    subs.push_back(nh.subscribe<tread_wear::WheelSlip>(prefix + "slip", 10000, [&, w](const auto& m) {
      std::lock_guard<std::mutex> lock(mutex);
      addSlip(&node, w, *m);
      ++received;
    }));
    subs.push_back(nh.subscribe<tread_wear::WheelSpeed>(prefix + "speed", 10000, [&, w](const auto& m) {
      std::lock_guard<std::mutex> lock(mutex);
      addSpeed(&node, w, *m);
      ++received;
    }));
  }
  // Play once the node listens to every sensor and the node's outputs reach this test.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  bool ready = false;
  while (!ready && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.1).sleep();
    ready = nodeSubscribed("/imu") && nodeSubscribed("/joint_states") && nodeSubscribed("/odom");
    for (const ros::Subscriber& s : subs) ready = ready && s.getNumPublishers() > 0;
  }
  ASSERT_TRUE(ready) << "vehicle_inputs_node did not come up";
  const pid_t player = fork();
  if (player == 0) {
    execl("/usr/lib/rosbag/play", "play", "--clock", "-q", "-d", "1", "-r", "3", sensor_bag.c_str(), "--topics",
          "/imu", "/joint_states", "/odom", "/tf_static", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(player, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";
  // The node may still be working through its queue on a loaded machine: wait until its outputs stop for 1 s.
  const ros::WallTime drain_deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  for (std::size_t before = SIZE_MAX; ros::WallTime::now() < drain_deadline;) {
    ros::WallDuration(1.0).sleep();
    std::lock_guard<std::mutex> lock(mutex);
    if (received == before) break;
    before = received;
  }

  std::lock_guard<std::mutex> lock(mutex);
  for (int w = 0; w < kWheels; ++w) {
    const auto i = static_cast<std::size_t>(w);
    SCOPED_TRACE(kNames[i]);
    std::size_t compared = 0, different = 0, incomplete = 0;
    for (const auto& entry : node[i]) {
      if (entry.second.parts != 3) {
        ++incomplete;  // load, slip or speed missing at this stamp
        continue;
      }
      const auto it = tool[i].find(entry.first);
      ASSERT_NE(it, tool[i].end()) << "the node published at " << entry.first << ", the tool did not";
      const Inputs& a = entry.second;
      const Inputs& b = it->second;
      ++compared;
      if (a.load_n != b.load_n || a.slip_angle_rad != b.slip_angle_rad || a.slip_ratio != b.slip_ratio ||
          a.path_curvature_per_m != b.path_curvature_per_m || a.speed_mps != b.speed_mps) {
        if (different++ < 3)
          ADD_FAILURE() << "at " << entry.first << ": node load " << a.load_n << " alpha " << a.slip_angle_rad
                        << " kappa " << a.slip_ratio << " v " << a.speed_mps << ", tool " << b.load_n << " "
                        << b.slip_angle_rad << " " << b.slip_ratio << " " << b.speed_mps;
      }
    }
    std::printf("%s: %zu stamps compared, %zu different, %zu incomplete, tool %zu (%.2f to %.2f s), node %.2f to "
                "%.2f s\n",
                kNames[i].c_str(), compared, different, incomplete, tool[i].size(), tool[i].begin()->first.toSec(),
                tool[i].rbegin()->first.toSec(), node[i].empty() ? 0.0 : node[i].begin()->first.toSec(),
                node[i].empty() ? 0.0 : node[i].rbegin()->first.toSec());
    EXPECT_EQ(different, 0u);
    // Every cycle but the tool's last (the end of the data, which the node never sees) reaches the node, complete.
    EXPECT_EQ(incomplete, 0u);
    EXPECT_EQ(compared, tool[i].size() - 1);
  }
  std::remove(sensor_bag.c_str());
  std::remove(tool_bag.c_str());
  std::remove(config.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_vehicle_inputs_bag_play");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
