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
/// The true inputs per wheel, keyed by stamp.
using TruthTable = std::array<std::unordered_map<long long, Truth>, kWheelCount>;

/// The sensor topics of the input bag (checked for their types).
struct SensorTopics {
  std::string imu, joints, odom, tf, info;
};

SensorTopics findSensorTopics(rosbag::Bag& in, const std::string& path) {
  std::map<std::string, const rosbag::ConnectionInfo*> connections;
  rosbag::View all(in);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) connections[c->topic] = c;
  SensorTopics t;
  t.imu = findTopic<sensor_msgs::Imu>(path, connections, kImuTopic, true);
  t.joints = findTopic<sensor_msgs::JointState>(path, connections, kJointStatesTopic, true);
  t.odom = findTopic<nav_msgs::Odometry>(path, connections, kOdometryTopic, true);
  t.tf = findTopic<TfStaticMessage>(path, connections, kTfStaticTopic, true);
  t.info = findTopic<std_msgs::String>(path, connections, kDriveInfoTopic, false);
  return t;
}

/// The IMU's mount base_link -> imu_link from /tf_static into the pipeline and the result.
void mountImu(rosbag::Bag& in, const std::string& path, const SensorTopics& topics, VehicleInputPipeline* pipeline,
              VehicleInputsResult* result) {
  rosbag::View tf_view(in, rosbag::TopicQuery(topics.tf));
  for (const rosbag::MessageInstance& m : tf_view) {
    const auto tf = m.instantiate<TfStaticMessage>();
    if (!tf) continue;
    for (const geometry_msgs::TransformStamped& t : tf->transforms) {
      if (withoutSlash(t.header.frame_id) != kBaseFrame || withoutSlash(t.child_frame_id) != kImuFrame) continue;
      const geometry_msgs::Quaternion& q = t.transform.rotation;
      const std::array<double, 3> origin{{t.transform.translation.x, t.transform.translation.y,
                                          t.transform.translation.z}};
      if (!pipeline->setImuMount({{q.x, q.y, q.z, q.w}}, origin))
        throw BagError(path + ": the base_link -> imu_link rotation on " + topics.tf + " is not a quaternion");
      result->imu_mount_rpy_rad = SensorModel::rpyOf({q.x, q.y, q.z, q.w});
      result->imu_position_m = origin;
      return;
    }
  }
  throw BagError(path + ": no base_link -> imu_link transform on " + topics.tf);
}

/// The odometry latency: median of record time - header stamp [s] (reported; the speed enters at its stamp).
double odometryLag(rosbag::Bag& in, const SensorTopics& topics) {
  std::vector<double> lags;
  rosbag::View odom_view(in, rosbag::TopicQuery(topics.odom));
  for (const rosbag::MessageInstance& m : odom_view) {
    const auto odom = m.instantiate<nav_msgs::Odometry>();
    if (odom) lags.push_back(m.getTime().toSec() - odom->header.stamp.toSec());
  }
  if (lags.empty()) return 0.0;
  std::nth_element(lags.begin(), lags.begin() + static_cast<std::ptrdiff_t>(lags.size() / 2), lags.end());
  return std::max(0.0, lags[lags.size() / 2]);
}

/// The true inputs wheels/<name>/{load,slip,speed}, if the bag has all of them (a generated drive).
bool readTruth(rosbag::Bag& in, const std::string& path, const std::array<std::string, kWheelCount>& names,
               TruthTable* truth) {
  std::map<std::string, const rosbag::ConnectionInfo*> connections;
  rosbag::View all(in);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) connections[c->topic] = c;
  std::map<std::string, std::pair<int, int>> truth_topics;  // topic -> wheel, kind (0 load, 1 slip, 2 speed)
  for (int w = 0; w < kWheelCount; ++w) {
    const WheelInputTopics t = wheelInputTopics(names[static_cast<std::size_t>(w)]);
    const std::string load = findTopic<WheelLoad>(path, connections, t.load, false);
    const std::string slip = findTopic<WheelSlip>(path, connections, t.slip, false);
    const std::string speed = findTopic<WheelSpeed>(path, connections, t.speed, false);
    if (load.empty() || slip.empty() || speed.empty()) return false;
    truth_topics[load] = {w, 0};
    truth_topics[slip] = {w, 1};
    truth_topics[speed] = {w, 2};
  }
  std::vector<std::string> topics;
  for (const auto& t : truth_topics) topics.push_back(t.first);
  rosbag::View truth_view(in, rosbag::TopicQuery(topics));
  for (const rosbag::MessageInstance& m : truth_view) {
    const auto route = truth_topics.at(m.getTopic());
    auto& map = (*truth)[static_cast<std::size_t>(route.first)];
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
  return true;
}

/// One wheel's estimate against the truth at the same stamp: load and slip angle when kGood, slip ratio when kGood
/// with a converged radius.
void score(const WheelInputEstimate& e, const Truth& tr, double static_load_n, std::size_t wheel,
           VehicleInputsResult* result) {
  if (std::isfinite(tr.load)) {
    if (e.load_quality == EstimateQuality::kGood)
      result->load[wheel].add((e.load_n - tr.load) / static_load_n);
    else
      ++result->load[wheel].skipped;
  }
  if (std::isfinite(tr.slip_angle)) {
    if (e.slip_angle_quality == EstimateQuality::kGood)
      result->slip_angle[wheel].add((e.slip_angle_rad - tr.slip_angle) * kRad2Deg);
    else
      ++result->slip_angle[wheel].skipped;
  }
  if (std::isfinite(tr.slip_ratio)) {
    if (e.slip_ratio_quality == EstimateQuality::kGood && (e.flags & kFlagRadiusNotConverged) == 0u)
      result->slip_ratio[wheel].add(e.slip_ratio - tr.slip_ratio);
    else
      ++result->slip_ratio[wheel].skipped;
  }
  if (std::isfinite(tr.speed)) {
    if (std::isfinite(e.speed_mps))
      result->speed[wheel].add(e.speed_mps - tr.speed);
    else
      ++result->speed[wheel].skipped;
  }
}

/// Writes each cycle's publishable wheels, as vehicle_inputs_node publishes them, and scores them.
class CycleWriter {
 public:
  CycleWriter(rosbag::Bag* out, const VehicleInputPipeline& pipeline, const TruthTable& truth,
              VehicleInputsResult* result)
      : out_(out), pipeline_(pipeline), truth_(truth), result_(result),
        vehicle_(pipeline.config().estimator.vehicle) {
    for (const std::string& name : pipeline.config().wheel_names) topics_.push_back(wheelInputTopics(name));
  }

  void operator()(double t) {
    ++result_->cycles;
    const VehicleInputEstimate& estimate = pipeline_.estimate();
    if (!estimate.valid) {
      ++result_->invalid_cycles;
      return;
    }
    const ros::Time stamp(t);
    const long long k = key(t);
    for (int i = 0; i < kWheelCount; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const WheelInputEstimate& e = estimate.wheels[ui];
      if (pipeline_.publishable(i)) write(stamp, topics_[ui], e);
      if (!result_->truth_present) continue;
      const auto it = truth_[ui].find(k);
      if (it != truth_[ui].end()) score(e, it->second, vehicle_.staticLoad(i), ui, result_);
    }
  }

 private:
  void write(const ros::Time& stamp, const WheelInputTopics& topics, const WheelInputEstimate& e) {
    load_.header.stamp = slip_.header.stamp = speed_.header.stamp = stamp;
    load_.header.frame_id = slip_.header.frame_id = speed_.header.frame_id = topics.frame;
    load_.load_n = e.load_n;
    slip_.slip_angle_rad = e.slip_angle_rad;
    slip_.slip_ratio = e.slip_ratio;
    slip_.path_curvature_per_m = e.path_curvature_per_m;
    speed_.speed_mps = e.speed_mps;
    out_->write(topics.load, stamp, load_);
    out_->write(topics.slip, stamp, slip_);
    out_->write(topics.speed, stamp, speed_);
  }

  rosbag::Bag* out_;
  const VehicleInputPipeline& pipeline_;
  const TruthTable& truth_;
  VehicleInputsResult* result_;
  VehicleModel vehicle_;
  std::vector<WheelInputTopics> topics_;
  WheelLoad load_;
  WheelSlip slip_;
  WheelSpeed speed_;
};

/// Feeds the sensors in record order, each at its header stamp, the cycles in input time (as the node with
/// input_time), then copies /drive/info.
void feedSensors(rosbag::Bag& in, const SensorTopics& topics, VehicleInputPipeline* pipeline, CycleWriter* writer,
                 rosbag::Bag* out, VehicleInputsResult* result) {
  double last_stamp = -std::numeric_limits<double>::infinity();  // of the IMU and joint states [s]
  rosbag::View sensors(in, rosbag::TopicQuery(std::vector<std::string>{topics.imu, topics.joints, topics.odom}));
  for (const rosbag::MessageInstance& m : sensors) {
    if (m.getTopic() == topics.imu) {
      const auto imu = m.instantiate<sensor_msgs::Imu>();
      if (!imu) continue;
      ++result->imu_messages;
      const double stamp = imu->header.stamp.toSec();
      last_stamp = std::max(last_stamp, stamp);
      pipeline->cyclesBefore(InputStream::kImu, stamp, *writer);
      pipeline->addImu(stamp, {{imu->linear_acceleration.x, imu->linear_acceleration.y, imu->linear_acceleration.z}},
                       {{imu->angular_velocity.x, imu->angular_velocity.y, imu->angular_velocity.z}});
    } else if (m.getTopic() == topics.joints) {
      const auto js = m.instantiate<sensor_msgs::JointState>();
      if (!js) continue;
      ++result->joint_state_messages;
      const double stamp = js->header.stamp.toSec();
      last_stamp = std::max(last_stamp, stamp);
      pipeline->cyclesBefore(InputStream::kJoints, stamp, *writer);
      pipeline->addJoints(stamp, js->name, js->position, js->velocity);
    } else {
      const auto odom = m.instantiate<nav_msgs::Odometry>();
      if (!odom) continue;
      ++result->odometry_messages;
      pipeline->addSpeed(odom->header.stamp.toSec(), odom->twist.twist.linear.x, odom->twist.twist.linear.y);
    }
  }
  if (std::isfinite(last_stamp)) pipeline->cyclesThrough(last_stamp, *writer);
  if (topics.info.empty()) return;
  rosbag::View info(in, rosbag::TopicQuery(topics.info));
  for (const rosbag::MessageInstance& m : info) {
    const auto text = m.instantiate<std_msgs::String>();
    if (text) out->write(kDriveInfoTopic, m.getTime(), *text);
  }
}

}  // namespace

VehicleInputsResult runVehicleInputs(const std::string& in_path, const std::string& out_path,
                                     const VehicleInputsOptions& options) {
  std::string error;
  if (!options.config.validate(&error)) throw BagError(in_path + ": front end configuration: " + error);
  checkBagRecords(in_path);  // also the error for a missing or unreadable file
  rosbag::Bag in;
  try {
    in.open(in_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": not a readable bag (corrupt, truncated or unindexed: try `rosbag reindex`): " +
                   e.what());
  }
  VehicleInputsResult result;
  VehicleInputsConfig config = options.config;
  config.input_time = true;  // the tool always runs in input time
  VehicleInputPipeline pipeline(config);
  TruthTable truth;
  SensorTopics topics;
  try {
    topics = findSensorTopics(in, in_path);
    mountImu(in, in_path, topics, &pipeline, &result);
    result.odometry_lag_s = odometryLag(in, topics);
    result.truth_present = readTruth(in, in_path, options.config.wheel_names, &truth);
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": cannot read the bag: " + e.what());
  }
  rosbag::Bag out;
  openBagForWriting(&out, out_path);
  CycleWriter writer(&out, pipeline, truth, &result);
  try {
    feedSensors(in, topics, &pipeline, &writer, &out, &result);
  } catch (const rosbag::BagException& e) {
    throw BagError(in_path + ": cannot read the bag: " + e.what());
  }
  out.close();
  if (result.imu_messages == 0 || result.joint_state_messages == 0 || result.odometry_messages == 0)
    throw BagError(in_path + ": a sensor topic has no messages (imu " + std::to_string(result.imu_messages) +
                   ", joint_states " + std::to_string(result.joint_state_messages) + ", odom " +
                   std::to_string(result.odometry_messages) + ")");
  const VehicleInputEstimator& estimator = pipeline.estimator();
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
