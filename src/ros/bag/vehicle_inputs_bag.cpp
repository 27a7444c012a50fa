#include "tread_wear/ros/bag/vehicle_inputs_bag.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/vehicle/sensor_model.h"
#include "tf_static_message.h"

namespace tread_wear {

void ErrorStat::add(double error) {
  sum_sq += error * error;
  worst = std::max(worst, std::fabs(error));
  ++scored;
}

double ErrorStat::rms() const {
  return scored > 0 ? std::sqrt(sum_sq / static_cast<double>(scored)) : std::numeric_limits<double>::quiet_NaN();
}

double ErrorStat::scoredShare() const {
  return scored + skipped > 0 ? static_cast<double>(scored) / static_cast<double>(scored + skipped) : 0.0;
}

namespace {

constexpr double kRad2Deg = 57.29577951308232;

std::string withoutSlash(const std::string& name) { return !name.empty() && name[0] == '/' ? name.substr(1) : name; }

/// The bag's topic of a given name (with or without the leading slash), checked for its type.
template <typename M>
std::string findTopic(const std::string& path, const std::map<std::string, const rosbag::ConnectionInfo*>& connections,
                      const std::string& name, bool required) {
  for (const auto& entry : connections) {
    if (withoutSlash(entry.first) != withoutSlash(name)) continue;
    const std::string expected = ros::message_traits::datatype<M>();
    if (entry.second->datatype != expected)
      throw BagError(path + ": topic " + entry.first + " has type " + entry.second->datatype + ", expected " +
                     expected);
    if (entry.second->md5sum != ros::message_traits::md5sum<M>())
      throw BagError(path + ": topic " + entry.first + " has a different definition of " + expected);
    return entry.first;
  }
  if (required)
    throw BagError(path + ": missing topic " + withoutSlash(name) + " (" + ros::message_traits::datatype<M>() + ")");
  return std::string();
}

/// Stamp key for matching the truth's samples with the estimate's cycles [us].
long long key(double t_s) { return std::llround(t_s * 1e6); }

struct Truth {
  double load = std::numeric_limits<double>::quiet_NaN();
  double slip_angle = std::numeric_limits<double>::quiet_NaN();
  double slip_ratio = std::numeric_limits<double>::quiet_NaN();
  double speed = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace

VehicleInputsResult runVehicleInputs(const std::string& in_path, const std::string& out_path,
                                     const VehicleInputsOptions& options) {
  if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz) ||
      options.wheel_names.size() != static_cast<std::size_t>(kWheelCount))
    throw BagError(out_path + ": the front end needs rate_hz > 0 and 4 wheel names");
  checkBagRecords(in_path);  // also the error for a missing or unreadable file
  rosbag::Bag in;
  try {
    in.open(in_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": not a readable bag (corrupt, truncated or unindexed: try `rosbag reindex`): " +
                   e.what());
  }
  VehicleInputsResult result;
  VehicleInputEstimatorParams params = options.estimator;
  std::map<std::string, const rosbag::ConnectionInfo*> connections;
  std::string imu_topic, joint_topic, odom_topic, tf_topic, info_topic;
  // truth per wheel, keyed by stamp
  std::array<std::unordered_map<long long, Truth>, kWheelCount> truth;
  try {
    rosbag::View all(in);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) connections[c->topic] = c;
    imu_topic = findTopic<sensor_msgs::Imu>(in_path, connections, kImuTopic, true);
    joint_topic = findTopic<sensor_msgs::JointState>(in_path, connections, kJointStatesTopic, true);
    odom_topic = findTopic<nav_msgs::Odometry>(in_path, connections, kOdometryTopic, true);
    tf_topic = findTopic<TfStaticMessage>(in_path, connections, kTfStaticTopic, true);
    info_topic = findTopic<std_msgs::String>(in_path, connections, kDriveInfoTopic, false);

    // The IMU mount.
    bool have_mount = false;
    rosbag::View tf_view(in, rosbag::TopicQuery(tf_topic));
    for (const rosbag::MessageInstance& m : tf_view) {
      const auto tf = m.instantiate<TfStaticMessage>();
      if (!tf) continue;
      for (const geometry_msgs::TransformStamped& t : tf->transforms) {
        if (withoutSlash(t.header.frame_id) != kBaseFrame || withoutSlash(t.child_frame_id) != kImuFrame) continue;
        const geometry_msgs::Quaternion& q = t.transform.rotation;
        const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!std::isfinite(norm) || norm < 1e-6)
          throw BagError(in_path + ": the base_link -> imu_link rotation on " + tf_topic + " is not a quaternion");
        params.imu_mount_rpy_rad = SensorModel::rpyOf({q.x, q.y, q.z, q.w});
        params.imu_position_m = {t.transform.translation.x, t.transform.translation.y, t.transform.translation.z};
        have_mount = true;
      }
    }
    if (!have_mount) throw BagError(in_path + ": no base_link -> imu_link transform on " + tf_topic);
    result.imu_mount_rpy_rad = params.imu_mount_rpy_rad;
    result.imu_position_m = params.imu_position_m;

    // The odometry latency: median of record time - header stamp.
    std::vector<double> lags;
    rosbag::View odom_view(in, rosbag::TopicQuery(odom_topic));
    for (const rosbag::MessageInstance& m : odom_view) {
      const auto odom = m.instantiate<nav_msgs::Odometry>();
      if (odom) lags.push_back(m.getTime().toSec() - odom->header.stamp.toSec());
    }
    if (!lags.empty()) {
      std::nth_element(lags.begin(), lags.begin() + static_cast<std::ptrdiff_t>(lags.size() / 2), lags.end());
      result.odometry_lag_s = std::max(0.0, lags[lags.size() / 2]);
    }
    params.speed_lag_s = result.odometry_lag_s;

    // The truth, if the bag has it (a generated drive).
    std::map<std::string, std::pair<int, int>> truth_topics;  // topic -> wheel, kind (0 load, 1 slip, 2 speed)
    for (int w = 0; w < kWheelCount; ++w) {
      const WheelInputTopics truth = wheelInputTopics(options.wheel_names[static_cast<std::size_t>(w)]);
      const std::string load = findTopic<WheelLoad>(in_path, connections, truth.load, false);
      const std::string slip = findTopic<WheelSlip>(in_path, connections, truth.slip, false);
      const std::string speed = findTopic<WheelSpeed>(in_path, connections, truth.speed, false);
      if (load.empty() || slip.empty() || speed.empty()) {
        truth_topics.clear();
        break;
      }
      truth_topics[load] = {w, 0};
      truth_topics[slip] = {w, 1};
      truth_topics[speed] = {w, 2};
    }
    if (!truth_topics.empty()) {
      std::vector<std::string> topics;
      for (const auto& t : truth_topics) topics.push_back(t.first);
      rosbag::View truth_view(in, rosbag::TopicQuery(topics));
      for (const rosbag::MessageInstance& m : truth_view) {
        const auto route = truth_topics.at(m.getTopic());
        auto& map = truth[static_cast<std::size_t>(route.first)];
        if (route.second == 0) {
          const auto msg = m.instantiate<WheelLoad>();
          if (msg) map[key(msg->header.stamp.toSec())].load = msg->load_n;
        } else if (route.second == 1) {
          const auto msg = m.instantiate<WheelSlip>();
          if (msg) {
            Truth& t = map[key(msg->header.stamp.toSec())];
            t.slip_angle = msg->slip_angle_rad;
            t.slip_ratio = msg->slip_ratio;
          }
        } else {
          const auto msg = m.instantiate<WheelSpeed>();
          if (msg) map[key(msg->header.stamp.toSec())].speed = msg->speed_mps;
        }
      }
      result.truth_present = true;
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": cannot read the bag: " + e.what());
  }

  std::string error;
  if (!params.validate(&error)) throw BagError(in_path + ": estimator parameters: " + error);
  VehicleInputEstimator estimator(params);
  const VehicleModel vehicle(params.vehicle);

  rosbag::Bag out;
  openBagForWriting(&out, out_path);
  std::vector<WheelInputTopics> topics;
  for (const std::string& name : options.wheel_names) topics.push_back(wheelInputTopics(name));
  WheelLoad load_msg;
  WheelSlip slip_msg;
  WheelSpeed speed_msg;
  VehicleInputEstimate estimate;
  const double dt = 1.0 / options.rate_hz;
  bool grid_started = false;
  double grid0 = 0.0, grid_end = 0.0;  // cycles up to the last IMU or joint_states sample
  std::size_t next = 0;

  auto cycle = [&](double t) {
    estimator.estimate(t, &estimate);
    ++result.cycles;
    if (!estimate.valid) {
      ++result.invalid_cycles;
      return;
    }
    const ros::Time stamp(t);
    const long long k = key(t);
    for (int i = 0; i < kWheelCount; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const WheelInputEstimate& e = estimate.wheels[ui];
      load_msg.header.stamp = slip_msg.header.stamp = speed_msg.header.stamp = stamp;
      load_msg.header.frame_id = slip_msg.header.frame_id = speed_msg.header.frame_id = topics[ui].frame;
      if (std::isfinite(e.load_n)) {
        load_msg.load_n = e.load_n;
        out.write(topics[ui].load, stamp, load_msg);
      }
      if (std::isfinite(e.slip_angle_rad) && std::isfinite(e.slip_ratio) && std::isfinite(e.path_curvature_per_m)) {
        slip_msg.slip_angle_rad = e.slip_angle_rad;
        slip_msg.slip_ratio = e.slip_ratio;
        slip_msg.path_curvature_per_m = e.path_curvature_per_m;
        out.write(topics[ui].slip, stamp, slip_msg);
      }
      if (std::isfinite(e.speed_mps)) {
        speed_msg.speed_mps = e.speed_mps;
        out.write(topics[ui].speed, stamp, speed_msg);
      }
      if (!result.truth_present) continue;
      const auto it = truth[ui].find(k);
      if (it == truth[ui].end()) continue;
      const Truth& tr = it->second;
      if (std::isfinite(tr.load)) {
        if (e.load_quality == EstimateQuality::kGood)
          result.load[ui].add((e.load_n - tr.load) / vehicle.staticLoad(i));
        else
          ++result.load[ui].skipped;
      }
      if (std::isfinite(tr.slip_angle)) {
        if (e.slip_angle_quality == EstimateQuality::kGood)
          result.slip_angle[ui].add((e.slip_angle_rad - tr.slip_angle) * kRad2Deg);
        else
          ++result.slip_angle[ui].skipped;
      }
      if (std::isfinite(tr.slip_ratio)) {
        if (e.slip_ratio_quality == EstimateQuality::kGood && (e.flags & kFlagRadiusNotConverged) == 0u)
          result.slip_ratio[ui].add(e.slip_ratio - tr.slip_ratio);
        else
          ++result.slip_ratio[ui].skipped;
      }
      if (std::isfinite(tr.speed)) {
        if (std::isfinite(e.speed_mps))
          result.speed[ui].add(e.speed_mps - tr.speed);
        else
          ++result.speed[ui].skipped;
      }
    }
  };
  // Runs every cycle strictly before t (samples at a cycle's own time are fed before it).
  auto advanceTo = [&](double t) {
    if (!grid_started) {
      grid0 = std::ceil(t * options.rate_hz - 1e-6) * dt;
      grid_started = true;
    }
    for (;;) {
      const double tc = grid0 + static_cast<double>(next) * dt;
      if (tc >= t - 1e-7 || tc > grid_end + 1e-7) break;
      cycle(tc);
      ++next;
    }
  };

  try {
    std::array<int, kWheelCount + 1> joint_index{};
    std::vector<std::string> last_names;
    grid_end = rosbag::View(in, rosbag::TopicQuery(std::vector<std::string>{imu_topic, joint_topic})).getEndTime().toSec();
    rosbag::View sensors(in, rosbag::TopicQuery(std::vector<std::string>{imu_topic, joint_topic, odom_topic}));
    for (const rosbag::MessageInstance& m : sensors) {
      const double record = m.getTime().toSec();
      advanceTo(record);
      if (m.getTopic() == imu_topic) {
        const auto imu = m.instantiate<sensor_msgs::Imu>();
        if (!imu) continue;
        ++result.imu_messages;
        estimator.addImu(imu->header.stamp.toSec(), imu->linear_acceleration.x, imu->linear_acceleration.y,
                         imu->linear_acceleration.z, imu->angular_velocity.x, imu->angular_velocity.y,
                         imu->angular_velocity.z);
      } else if (m.getTopic() == joint_topic) {
        const auto js = m.instantiate<sensor_msgs::JointState>();
        if (!js) continue;
        ++result.joint_state_messages;
        if (js->name != last_names) {
          last_names = js->name;
          for (int j = 0; j <= kWheelCount; ++j) {
            const auto it = std::find(js->name.begin(), js->name.end(), kJointNames[j]);
            joint_index[static_cast<std::size_t>(j)] =
                it == js->name.end() ? -1 : static_cast<int>(it - js->name.begin());
          }
        }
        const double stamp = js->header.stamp.toSec();
        std::array<double, kWheelCount> omega{};
        for (int j = 0; j < kWheelCount; ++j) {
          const int idx = joint_index[static_cast<std::size_t>(j)];
          if (idx < 0 || static_cast<std::size_t>(idx) >= js->velocity.size()) {
            omega[static_cast<std::size_t>(j)] = std::numeric_limits<double>::quiet_NaN();  // rejected, counted
          } else {
            omega[static_cast<std::size_t>(j)] = js->velocity[static_cast<std::size_t>(idx)];
          }
        }
        estimator.addWheelSpeeds(stamp, omega);
        const int steer = joint_index[kWheelCount];
        if (steer >= 0 && static_cast<std::size_t>(steer) < js->position.size())
          estimator.addSteering(stamp, js->position[static_cast<std::size_t>(steer)]);
      } else {
        const auto odom = m.instantiate<nav_msgs::Odometry>();
        if (!odom) continue;
        ++result.odometry_messages;
        estimator.addSpeed(record, std::fabs(odom->twist.twist.linear.x));
      }
    }
    if (grid_started) advanceTo(grid_end + 0.5 * dt);
    if (!info_topic.empty()) {
      rosbag::View info(in, rosbag::TopicQuery(info_topic));
      for (const rosbag::MessageInstance& m : info) {
        const auto text = m.instantiate<std_msgs::String>();
        if (text) out.write(kDriveInfoTopic, m.getTime(), *text);
      }
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": cannot read the bag: " + e.what());
  }
  out.close();
  if (result.imu_messages == 0 || result.joint_state_messages == 0 || result.odometry_messages == 0)
    throw BagError(in_path + ": a sensor topic has no messages (imu " + std::to_string(result.imu_messages) +
                   ", joint_states " + std::to_string(result.joint_state_messages) + ", odom " +
                   std::to_string(result.odometry_messages) + ")");
  result.radii = estimator.rollingRadii();
  for (int i = 0; i < kWheelCount; ++i) result.radius_converged[static_cast<std::size_t>(i)] = estimator.radiusConverged(i);
  for (int s = 0; s < kSensorCount; ++s) {
    for (int f = 1; f < kSampleFaultCount; ++f) {
      const std::uint64_t count = estimator.faultCount(static_cast<Sensor>(s), static_cast<SampleFault>(f));
      result.faults[static_cast<std::size_t>(s)][static_cast<std::size_t>(f)] = count;
      if (static_cast<SampleFault>(f) != SampleFault::kStale) result.rejected_samples += count;
    }
  }
  return result;
}

}  // namespace tread_wear
