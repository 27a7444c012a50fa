#include "tread_wear/ros/vehicle_inputs_node.h"

#include <tf2/LinearMath/Quaternion.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <sstream>

#include "tread_wear/io/rolling_radius_store.h"
#include "tread_wear/pipeline/loop_clock.h"

namespace tread_wear {
namespace {

const char* steerSourceName(SteerSource s) { return s == SteerSource::kMeasured ? "measured" : "none (single-track model)"; }

constexpr std::array<SampleFault, 5> kRejections{{SampleFault::kNotFinite, SampleFault::kOutOfOrder,
                                                  SampleFault::kOutOfRange, SampleFault::kFrozen,
                                                  SampleFault::kStale}};

std::uint64_t rejectedCount(const VehicleInputEstimator& e, Sensor s) {
  return e.faultCount(s, SampleFault::kNotFinite) + e.faultCount(s, SampleFault::kOutOfOrder) +
         e.faultCount(s, SampleFault::kOutOfRange) + e.faultCount(s, SampleFault::kFrozen);
}

// Fallback in use when a sensor is missing (docs/vehicle_inputs.md, Fallbacks).
const char* fallbackOf(Sensor s) {
  switch (s) {
    case Sensor::kImu: return "loads and lateral model on the flat-road fallback (speed derivative), yaw rate from wheels";
    case Sensor::kWheelSpeed: return "speed from the reference speed / IMU dead reckoning; slip ratio from the force demand";
    case Sensor::kSteering: return "front slip angles from the single-track model";
    case Sensor::kSpeed: return "no rolling-radius learning; speed from wheels + IMU";
  }
  return "";
}

std_msgs::ColorRGBA rgba(double r, double g, double b, double a) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = static_cast<float>(a);
  return c;
}

}  // namespace

void appendVehicleMarkers(const VehicleInputsConfig& config, const VehicleInputEstimate& estimate,
                          const std::array<WheelWearView, kWheelCount>& wear, const ros::Time& stamp,
                          visualization_msgs::MarkerArray* array) {
  const VehicleParams& v = config.estimator.vehicle;
  const double cx = config.cog_position_m[0], cy = config.cog_position_m[1];
  const double lf = v.cog_to_front_axle_m, lr = v.cogToRearAxle_m();
  const std::array<double, kWheelCount> x{{cx + lf, cx + lf, cx - lr, cx - lr}};
  const std::array<double, kWheelCount> y{
      {cy + v.track_front_m / 2, cy - v.track_front_m / 2, cy + v.track_rear_m / 2, cy - v.track_rear_m / 2}};
  const double radius = config.estimator.wheel_radius_m[0];
  visualization_msgs::Marker m;
  m.header.frame_id = config.base_frame;
  m.header.stamp = stamp;
  m.action = visualization_msgs::Marker::ADD;
  m.ns = "vehicle/body";
  m.id = 0;
  m.type = visualization_msgs::Marker::CUBE;
  m.pose.position.x = cx + 0.5 * (lf - lr);
  m.pose.position.y = cy;
  m.pose.position.z = radius + 0.35;
  m.pose.orientation.w = 1.0;
  m.scale.x = v.wheelbase_m + 2.0 * radius + 0.6;
  m.scale.y = std::max(v.track_front_m, v.track_rear_m) + 0.1;
  m.scale.z = 0.5;
  m.color = rgba(0.55, 0.6, 0.7, 0.25);
  array->markers.push_back(m);
  for (int i = 0; i < kWheelCount; ++i) {
    visualization_msgs::Marker w = m;
    w.ns = "vehicle/wheels";
    w.id = i;
    w.type = visualization_msgs::Marker::CYLINDER;
    w.pose.position.x = x[i];
    w.pose.position.y = y[i];
    w.pose.position.z = radius;
    // Cylinder axis (z) along the wheel's axle: roll by 90 deg, then yaw by the steer angle.
    const double steer = std::isfinite(estimate.wheels[i].steer_angle_rad) ? estimate.wheels[i].steer_angle_rad : 0.0;
    tf2::Quaternion q;
    q.setRPY(M_PI / 2.0, 0.0, steer);
    w.pose.orientation.x = q.x();
    w.pose.orientation.y = q.y();
    w.pose.orientation.z = q.z();
    w.pose.orientation.w = q.w();
    w.scale.x = w.scale.y = 2.0 * radius;
    w.scale.z = 0.2;
    w.color = rgba(0.15, 0.15, 0.15, 0.6);
    array->markers.push_back(w);
  }
  visualization_msgs::Marker label = m;
  label.ns = "vehicle/label";
  label.id = 0;
  label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  label.pose.position.z = radius + 1.0;
  label.scale.x = label.scale.y = 0.0;
  label.scale.z = 0.18;
  label.color = rgba(1.0, 1.0, 1.0, 1.0);
  char text[256];
  std::snprintf(text, sizeof(text), "v %.1f m/s, r %.3f rad/s\nf_x %.2f, f_y %.2f m/s^2\nspeed: %s, yaw: %s, accel: %s",
                estimate.speed_mps, estimate.yaw_rate_rps, estimate.long_specific_force_mps2,
                estimate.lat_specific_force_mps2, speedSourceName(estimate.speed_source),
                yawRateSourceName(estimate.yaw_rate_source), accelSourceName(estimate.accel_source));
  label.text = estimate.valid ? text : "no speed source: nothing published";
  array->markers.push_back(label);
  for (int i = 0; i < kWheelCount; ++i) {
    // Beside the tire, outboard, above the road: readable from above at the scale of the car.
    const WheelInputEstimate& w = estimate.wheels[static_cast<std::size_t>(i)];
    visualization_msgs::Marker l = label;
    l.header.frame_id = config.wheel_frames[static_cast<std::size_t>(i)];
    l.ns = "vehicle/wheel_labels";
    l.id = i;
    l.pose.position.x = 0.0;
    l.pose.position.y = (i % 2 == 0) ? 0.75 : -0.75;
    l.pose.position.z = 0.3;
    l.scale.z = 0.14;
    int n = std::snprintf(text, sizeof(text), "%s\nFz %.2f kN\nalpha %.2f deg, kappa %.4f",
                          config.wheel_names[static_cast<std::size_t>(i)].c_str(), w.load_n * 1e-3,
                          w.slip_angle_rad * 180.0 / M_PI, w.slip_ratio);
    const WheelWearView& v = wear[static_cast<std::size_t>(i)];
    if (n > 0 && n < static_cast<int>(sizeof(text)) && std::isfinite(v.wear_rate_kg_per_m))
      std::snprintf(text + n, sizeof(text) - static_cast<std::size_t>(n), "\nwear %.2f mg/km, loss %.3f mg",
                    v.wear_rate_kg_per_m * 1e9, v.accumulated_loss_kg * 1e6);
    l.text = text;
    l.color = wheelPublishable(estimate, i) ? rgba(1.0, 1.0, 0.6, 1.0) : rgba(1.0, 0.4, 0.4, 1.0);
    array->markers.push_back(l);
  }
}

void fillInputQuality(const VehicleInputEstimate& e, int wheel, bool published, tread_wear::WheelInputQuality* msg) {
  const WheelInputQualityRecord q = inputQuality(e, wheel);
  msg->load_quality = static_cast<std::uint8_t>(q.load_quality);
  msg->slip_angle_quality = static_cast<std::uint8_t>(q.slip_angle_quality);
  msg->slip_ratio_quality = static_cast<std::uint8_t>(q.slip_ratio_quality);
  msg->flags = q.flags;
  msg->speed_source = static_cast<std::uint8_t>(q.speed_source);
  msg->yaw_rate_source = static_cast<std::uint8_t>(q.yaw_rate_source);
  msg->accel_source = static_cast<std::uint8_t>(q.accel_source);
  msg->published = published;
  msg->steer_angle_rad = q.steer_angle_rad;
  msg->rolling_radius_m = q.rolling_radius_m;
}

void publishWheelInputs(const VehicleInputEstimate& estimate, const ros::Time& now,
                        std::array<VehicleInputPublishers, kWheelCount>* publishers, CycleStats* stats,
                        bool wait_for_slot) {
  if (!estimate.valid) ++stats->invalid_cycles;
  for (int i = 0; i < kWheelCount; ++i) {
    const bool publish = wheelPublishable(estimate, i);
    const WheelInputEstimate& w = estimate.wheels[static_cast<std::size_t>(i)];
    VehicleInputPublishers& p = (*publishers)[static_cast<std::size_t>(i)];
    bool published = false;
    if (publish) {
      published = true;
      if (wait_for_slot ? p.load->lock() : p.load->trylock()) {
        p.load->msg().header.stamp = now;
        p.load->msg().load_n = w.load_n;
        p.load->unlockAndPublish();
      } else {
        ++stats->skipped_publications;
        published = false;
      }
      if (wait_for_slot ? p.slip->lock() : p.slip->trylock()) {
        p.slip->msg().header.stamp = now;
        p.slip->msg().slip_angle_rad = w.slip_angle_rad;
        p.slip->msg().slip_ratio = w.slip_ratio;
        p.slip->msg().path_curvature_per_m = w.path_curvature_per_m;
        p.slip->unlockAndPublish();
      } else {
        ++stats->skipped_publications;
        published = false;
      }
      if (wait_for_slot ? p.speed->lock() : p.speed->trylock()) {
        p.speed->msg().header.stamp = now;
        p.speed->msg().speed_mps = w.speed_mps;
        p.speed->unlockAndPublish();
      } else {
        ++stats->skipped_publications;
        published = false;
      }
      ++stats->published[static_cast<std::size_t>(i)];
    } else {
      ++stats->withheld[static_cast<std::size_t>(i)];
    }
    if (wait_for_slot ? p.quality->lock() : p.quality->trylock()) {
      p.quality->msg().header.stamp = now;
      fillInputQuality(estimate, i, published, &p.quality->msg());
      p.quality->unlockAndPublish();
    } else {
      ++stats->skipped_publications;
    }
  }
}

VehicleInputsNode::VehicleInputsNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

VehicleInputsNode::~VehicleInputsNode() { shutdown(); }

bool VehicleInputsNode::initialize() {
  std::string error;
  if (!loadVehicleInputsConfig(pnh_, &config_, &error)) {
    ROS_FATAL("vehicle_inputs_node: invalid configuration: %s", error.c_str());
    return false;
  }
  ROS_INFO_STREAM("vehicle_inputs_node parameters:\n" << config_.describe());
  pipeline_ = std::make_unique<VehicleInputPipeline>(config_);

  if (!config_.radius_file.empty()) {
    std::array<RollingRadiusState, kWheelCount> radii{};
    std::string load_error;
    const RadiusLoadStatus s = loadRollingRadii(config_.radius_file, config_.wheel_names, &radii, &load_error);
    radius_restore_ = radiusLoadStatusName(s);
    if (s == RadiusLoadStatus::kLoaded) {
      if (pipeline_->restoreRollingRadii(radii)) {
        ROS_INFO("vehicle_inputs_node: rolling radii restored from %s", config_.radius_file.c_str());
      } else {
        radius_restore_ = "rejected";
        ROS_ERROR("vehicle_inputs_node: rolling radii in %s rejected by the estimator; starting nominal",
                  config_.radius_file.c_str());
      }
    } else if (s == RadiusLoadStatus::kInvalid) {
      ROS_ERROR("vehicle_inputs_node: %s; starting from the nominal radii", load_error.c_str());
    }
  }

  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_, nh_);
  // In input time (a bag played faster than it was recorded) every output counts: roscpp drops the oldest message of
  // a subscriber's outgoing queue once it holds more than the advertised size, so the queues are as deep as the
  // inputs'.
  const std::uint32_t out_queue = config_.input_time ? 10000 : 10;
  for (int i = 0; i < kWheelCount; ++i) {
    const std::string prefix = "wheels/" + config_.wheel_names[i] + "/";
    VehicleInputPublishers& p = publishers_[i];
    p.load = std::make_unique<RealtimePublisher<tread_wear::WheelLoad>>(
        nh_.advertise<tread_wear::WheelLoad>(prefix + "load", out_queue));
    p.slip = std::make_unique<RealtimePublisher<tread_wear::WheelSlip>>(
        nh_.advertise<tread_wear::WheelSlip>(prefix + "slip", out_queue));
    p.speed = std::make_unique<RealtimePublisher<tread_wear::WheelSpeed>>(
        nh_.advertise<tread_wear::WheelSpeed>(prefix + "speed", out_queue));
    p.quality = std::make_unique<RealtimePublisher<tread_wear::WheelInputQuality>>(
        nh_.advertise<tread_wear::WheelInputQuality>(prefix + "input_quality", out_queue));
    // Preallocated: frame ids and the wheel name are set once, the cycle writes numbers only.
    p.load->msg().header.frame_id = config_.base_frame;
    p.slip->msg().header.frame_id = config_.base_frame;
    p.speed->msg().header.frame_id = config_.base_frame;
    p.quality->msg().header.frame_id = config_.base_frame;
    p.quality->msg().wheel = config_.wheel_names[i];
  }
  const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
  // In input time every sample counts (a dropped one changes the result): keep a backlog of a fast replay.
  const std::uint32_t queue = config_.input_time ? 10000 : 50;
  imu_sub_ = nh_.subscribe("imu", queue, &VehicleInputsNode::imuCallback, this, hints);
  joint_sub_ = nh_.subscribe("joint_states", queue, &VehicleInputsNode::jointCallback, this, hints);
  if (config_.speed_source == "odom")
    speed_sub_ = nh_.subscribe("odom", queue, &VehicleInputsNode::odomCallback, this, hints);
  else
    speed_sub_ = nh_.subscribe("speed", queue, &VehicleInputsNode::twistCallback, this, hints);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh_, pnh_);
  updater_->setHardwareID("vehicle_inputs");
  updater_->add("sensors", this, &VehicleInputsNode::sensorDiagnostics);
  for (int i = 0; i < kWheelCount; ++i)
    updater_->add("wheel " + config_.wheel_names[i],
                  [this, i](diagnostic_updater::DiagnosticStatusWrapper& stat) { wheelDiagnostics(i, stat); });
  updater_->add("publish cycle", this, &VehicleInputsNode::cycleDiagnostics);
  updater_->add("rolling radii", this, &VehicleInputsNode::radiusDiagnostics);
  diagnostics_timer_ = nh_.createWallTimer(ros::WallDuration(config_.diagnostic_period_s),
                                           [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  if (!config_.radius_file.empty())
    save_timer_ = nh_.createWallTimer(ros::WallDuration(config_.save_interval_s),
                                      [this](const ros::WallTimerEvent&) { saveRadii("periodic"); });
  // In input time the intake runs the cycles (inputTimeCycles); else the timer, on the node's clock.
  if (!config_.input_time)
    cycle_timer_ = nh_.createTimer(ros::Duration(1.0 / config_.publish_rate_hz), &VehicleInputsNode::cycle, this);
  if (config_.marker_rate_hz > 0.0) {
    marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("vehicle_markers", 1);
    for (int i = 0; i < kWheelCount; ++i)
      wear_subs_[static_cast<std::size_t>(i)] = nh_.subscribe<tread_wear::WheelWear>(
          "wheels/" + config_.wheel_names[i] + "/wear", 1, [this, i](const tread_wear::WheelWear::ConstPtr& m) {
            wear_[static_cast<std::size_t>(i)].wear_rate_kg_per_m = m->wear_rate_kg_per_m;
            wear_[static_cast<std::size_t>(i)].accumulated_loss_kg = m->accumulated_loss_kg;
          });
    marker_timer_ =
        nh_.createTimer(ros::Duration(1.0 / config_.marker_rate_hz), &VehicleInputsNode::publishMarkers, this);
  }
  return true;
}

void VehicleInputsNode::shutdown() {
  if (shut_down_ || !pipeline_) return;
  shut_down_ = true;
  cycle_timer_.stop();
  marker_timer_.stop();
  diagnostics_timer_.stop();
  save_timer_.stop();
  saveRadii("shutdown");
  for (VehicleInputPublishers& p : publishers_) {
    if (p.load) p.load->stop();
    if (p.slip) p.slip->stop();
    if (p.speed) p.speed->stop();
    if (p.quality) p.quality->stop();
  }
}

bool VehicleInputsNode::imuTransform(const std::string& frame_id) {
  if (imu_tf_ok_ && frame_id == imu_frame_) return true;
  if (frame_id.empty()) {
    imu_tf_error_ = "IMU header.frame_id is empty";
    return false;
  }
  // A missing transform is looked up again at most twice a second (a failed lookup costs an exception).
  const ros::WallTime wall = ros::WallTime::now();
  if (frame_id == imu_frame_attempted_ && !last_tf_attempt_.isZero() && (wall - last_tf_attempt_).toSec() < 0.5)
    return false;
  imu_frame_attempted_ = frame_id;
  last_tf_attempt_ = wall;
  geometry_msgs::TransformStamped tf;
  try {
    tf = tf_buffer_.lookupTransform(config_.base_frame, frame_id, ros::Time(0), ros::Duration(config_.tf_timeout_s));
  } catch (const tf2::TransformException& e) {
    imu_tf_error_ = e.what();
    imu_tf_ok_ = false;
    return false;
  }
  const geometry_msgs::Quaternion& q = tf.transform.rotation;
  const geometry_msgs::Vector3& t = tf.transform.translation;
  if (!pipeline_->setImuMount({{q.x, q.y, q.z, q.w}}, {{t.x, t.y, t.z}})) {
    imu_tf_error_ = "the transform " + config_.base_frame + " <- " + frame_id + " is not a rotation";
    imu_tf_ok_ = false;
    return false;
  }
  imu_frame_ = frame_id;
  imu_tf_ok_ = true;
  imu_tf_error_.clear();
  const std::array<double, 3>& lever = pipeline_->imuLeverArm_m();
  ROS_INFO("vehicle_inputs_node: IMU frame %s -> %s found; lever arm from the CoG [%.3f, %.3f, %.3f] m",
           frame_id.c_str(), config_.base_frame.c_str(), lever[0], lever[1], lever[2]);
  return true;
}

void VehicleInputsNode::inputTimeCycles(InputStream stream, const ros::Time& stamp) {
  if (!config_.input_time) return;
  pipeline_->cyclesBefore(stream, stamp.toSec(), [this](double t_s) {
    const ros::Time cycle_stamp(t_s);
    publishWheelInputs(pipeline_->estimate(), cycle_stamp, &publishers_, &stats_, true);
    ++stats_.cycles;
  });
}

void VehicleInputsNode::imuCallback(const sensor_msgs::Imu::ConstPtr& msg) {
  inputTimeCycles(InputStream::kImu, msg->header.stamp);
  ++imu_received_;
  if (!imuTransform(msg->header.frame_id)) {
    ++imu_without_tf_;
    return;
  }
  pipeline_->addImu(msg->header.stamp.toSec(),
                    {{msg->linear_acceleration.x, msg->linear_acceleration.y, msg->linear_acceleration.z}},
                    {{msg->angular_velocity.x, msg->angular_velocity.y, msg->angular_velocity.z}});
}

void VehicleInputsNode::jointCallback(const sensor_msgs::JointState::ConstPtr& msg) {
  inputTimeCycles(InputStream::kJoints, msg->header.stamp);
  pipeline_->addJoints(msg->header.stamp.toSec(), msg->name, msg->position, msg->velocity);
}

void VehicleInputsNode::odomCallback(const nav_msgs::Odometry::ConstPtr& msg) {
  pipeline_->addSpeed(msg->header.stamp.toSec(), msg->twist.twist.linear.x, msg->twist.twist.linear.y);
}

void VehicleInputsNode::twistCallback(const geometry_msgs::TwistWithCovarianceStamped::ConstPtr& msg) {
  pipeline_->addSpeed(msg->header.stamp.toSec(), msg->twist.twist.linear.x, msg->twist.twist.linear.y);
}

void VehicleInputsNode::cycle(const ros::TimerEvent& event) {
  // Real time: no allocation, no logging, no blocking I/O from here to the end.
  const double cpu0_s = threadCpuNow_s(), wall0_s = steadyNow_s();
  const double period_s = 1.0 / config_.publish_rate_hz;
  bool overrun = !event.last_real.isZero() && (event.current_real - event.current_expected).toSec() > period_s;
  const ros::Time now = event.current_real.isZero() ? ros::Time::now() : event.current_real;
  // A backward clock (a looped bag, a sim-time reset) is refused; the next sample restarts the estimator.
  if (!pipeline_->cycle(now.toSec())) ++stats_.clock_faults;
  publishWheelInputs(pipeline_->estimate(), now, &publishers_, &stats_);
  const double cpu_us = 1e6 * (threadCpuNow_s() - cpu0_s), wall_us = 1e6 * (steadyNow_s() - wall0_s);
  ++stats_.cycles;
  stats_.last_cpu_us = cpu_us;
  stats_.sum_cpu_us += cpu_us;
  if (cpu_us > stats_.max_cpu_us) stats_.max_cpu_us = cpu_us;
  stats_.last_wall_us = wall_us;
  if (wall_us > stats_.max_wall_us) stats_.max_wall_us = wall_us;
  if (wall_us > 1e6 * period_s) overrun = true;
  if (overrun) ++stats_.overruns;
}

void VehicleInputsNode::publishMarkers(const ros::TimerEvent&) {
  if (marker_pub_.getNumSubscribers() == 0) return;
  visualization_msgs::MarkerArray array;
  appendVehicleMarkers(config_, pipeline_->estimate(), wear_, ros::Time::now(), &array);
  marker_pub_.publish(array);
}

void VehicleInputsNode::saveRadii(const char* why) {
  if (config_.radius_file.empty() || !pipeline_) return;
  std::string error;
  if (saveRollingRadii(config_.radius_file, config_.wheel_names, pipeline_->estimator().rollingRadii(), wallNow_s(), &error)) {
    radius_save_error_.clear();
    last_save_ = ros::WallTime::now();
  } else {
    radius_save_error_ = error;
    ROS_ERROR_THROTTLE(60.0, "vehicle_inputs_node: %s save of the rolling radii failed: %s", why, error.c_str());
  }
}

void VehicleInputsNode::sensorDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  int level = diagnostic_msgs::DiagnosticStatus::OK;
  std::ostringstream message;
  const VehicleInputEstimator& e = pipeline_->estimator();
  const VehicleInputEstimate& estimate = pipeline_->estimate();
  const IntakeCounters& intake = pipeline_->counters();
  for (int s = 0; s < kSensorCount; ++s) {
    const Sensor sensor = static_cast<Sensor>(s);
    const std::string name = sensorName(sensor);
    const bool fresh = estimate.sensor_fresh[static_cast<std::size_t>(s)];
    stat.add(name + " fresh", fresh);
    for (SampleFault f : kRejections)
      stat.addf(name + " " + sampleFaultName(f), "%lu", static_cast<unsigned long>(e.faultCount(sensor, f)));
    const std::uint64_t rejected = rejectedCount(e, sensor);
    if (!fresh) {
      level = std::max<int>(level, diagnostic_msgs::DiagnosticStatus::WARN);
      message << name << " missing or stale: " << fallbackOf(sensor) << "; ";
    }
    if (rejected > rejected_at_last_report_[static_cast<std::size_t>(s)]) {
      level = std::max<int>(level, diagnostic_msgs::DiagnosticStatus::WARN);
      message << (rejected - rejected_at_last_report_[static_cast<std::size_t>(s)]) << " " << name
              << " samples rejected; ";
    }
    rejected_at_last_report_[static_cast<std::size_t>(s)] = rejected;
  }
  stat.add("imu tf", imu_tf_ok_ ? "ok (" + imu_frame_ + " -> " + config_.base_frame + ")" : "missing: " + imu_tf_error_);
  stat.addf("imu samples received", "%lu", static_cast<unsigned long>(imu_received_));
  stat.addf("imu samples without tf", "%lu", static_cast<unsigned long>(imu_without_tf_));
  if (!imu_tf_ok_ && imu_received_ > 0) {
    level = std::max<int>(level, diagnostic_msgs::DiagnosticStatus::WARN);
    message << "no transform " << config_.base_frame << " <- IMU frame: IMU not used; ";
  }
  stat.addf("joint_states received", "%lu", static_cast<unsigned long>(intake.joints));
  stat.addf("joint_states without all wheel joints", "%lu", static_cast<unsigned long>(intake.joints_without_wheels));
  stat.addf("joint_states without steering joint", "%lu", static_cast<unsigned long>(intake.joints_without_steering));
  stat.addf("speed received", "%lu", static_cast<unsigned long>(intake.speed));
  stat.add("speed source", speedSourceName(estimate.speed_source));
  stat.add("yaw rate source", yawRateSourceName(estimate.yaw_rate_source));
  stat.add("acceleration source", accelSourceName(estimate.accel_source));
  stat.add("steering source", steerSourceName(estimate.steer_source));
  stat.add("valid", estimate.valid);
  stat.addf("speed [m/s]", "%.3f", estimate.speed_mps);
  stat.addf("yaw rate [rad/s]", "%.4f", estimate.yaw_rate_rps);
  stat.addf("gated wheel updates", "%lu", static_cast<unsigned long>(e.gatedWheelUpdates()));
  if (!estimate.valid) {
    level = diagnostic_msgs::DiagnosticStatus::ERROR;
    message << "no speed source: nothing published; ";
  }
  const std::string text = message.str();
  stat.summary(static_cast<unsigned char>(level), text.empty() ? "all sensors fresh" : text);
}

void VehicleInputsNode::wheelDiagnostics(int wheel, diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const WheelInputEstimate& w = pipeline_->estimate().wheels[static_cast<std::size_t>(wheel)];
  const bool publishable = pipeline_->publishable(wheel);
  int level = diagnostic_msgs::DiagnosticStatus::OK;
  for (EstimateQuality q : {w.load_quality, w.slip_angle_quality, w.slip_ratio_quality})
    if (q == EstimateQuality::kDegraded) level = std::max<int>(level, diagnostic_msgs::DiagnosticStatus::WARN);
  if (!publishable) level = diagnostic_msgs::DiagnosticStatus::ERROR;
  stat.addf("load [N]", "%.1f", w.load_n);
  stat.addf("slip angle [rad]", "%.5f", w.slip_angle_rad);
  stat.addf("slip ratio [-]", "%.5f", w.slip_ratio);
  stat.addf("path curvature [1/m]", "%.5f", w.path_curvature_per_m);
  stat.addf("speed [m/s]", "%.3f", w.speed_mps);
  stat.addf("steer angle [rad]", "%.5f", w.steer_angle_rad);
  stat.addf("rolling radius [m]", "%.5f", w.rolling_radius_m);
  stat.add("radius converged", pipeline_->estimator().radiusConverged(wheel));
  stat.add("load quality", estimateQualityName(w.load_quality));
  stat.add("slip angle quality", estimateQualityName(w.slip_angle_quality));
  stat.add("slip ratio quality", estimateQualityName(w.slip_ratio_quality));
  stat.addf("flags", "0x%x", w.flags);
  stat.addf("published cycles", "%lu", static_cast<unsigned long>(stats_.published[static_cast<std::size_t>(wheel)]));
  stat.addf("withheld cycles", "%lu", static_cast<unsigned long>(stats_.withheld[static_cast<std::size_t>(wheel)]));
  std::string text = publishable ? (level == 0 ? "ok" : "degraded (fallback in use)") : "invalid: not published";
  if (w.flags & kFlagNoImu) text += "; no IMU";
  if (w.flags & kFlagWheelSpeedMissing) text += "; wheel speed missing";
  if (w.flags & kFlagWheelFrozen) text += "; wheel speed frozen";
  if (w.flags & kFlagSteeringModel) text += "; steering from the single-track model";
  if (w.flags & kFlagRadiusNotConverged) text += "; radius not converged";
  if (w.flags & kFlagLowSpeed) text += "; low speed";
  if (w.flags & kFlagSlipRatioFromForce) text += "; slip ratio from the force demand";
  stat.summary(static_cast<unsigned char>(level), text);
}

void VehicleInputsNode::cycleDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  stat.addf("cycles", "%lu", static_cast<unsigned long>(stats_.cycles));
  stat.addf("publish rate [Hz]", "%.1f", config_.publish_rate_hz);
  stat.addf("last cycle CPU [us]", "%.1f", stats_.last_cpu_us);
  stat.addf("mean cycle CPU [us]", "%.1f", stats_.cycles ? stats_.sum_cpu_us / stats_.cycles : 0.0);
  stat.addf("max cycle CPU [us]", "%.1f", stats_.max_cpu_us);
  stat.addf("last cycle wall [us]", "%.1f", stats_.last_wall_us);
  stat.addf("max cycle wall [us]", "%.1f", stats_.max_wall_us);
  stat.addf("deadline overruns", "%lu", static_cast<unsigned long>(stats_.overruns));
  stat.addf("skipped publications", "%lu", static_cast<unsigned long>(stats_.skipped_publications));
  stat.addf("clock faults", "%lu", static_cast<unsigned long>(stats_.clock_faults));
  stat.addf("estimator restarts", "%lu", static_cast<unsigned long>(pipeline_->counters().restarts));
  stat.addf("cycles without speed source", "%lu", static_cast<unsigned long>(stats_.invalid_cycles));
  if (stats_.clock_faults > 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                 "clock went backwards: estimate refused, estimator restarted (learned radii kept)");
  else if (stats_.overruns > 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "deadline overruns");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "on time");
}

void VehicleInputsNode::radiusDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  stat.add("radius_file", config_.radius_file.empty() ? std::string("(none)") : config_.radius_file);
  stat.add("restore", radius_restore_);
  if (!last_save_.isZero()) stat.addf("seconds since last save", "%.1f", (ros::WallTime::now() - last_save_).toSec());
  for (int i = 0; i < kWheelCount; ++i) {
    const RollingRadiusState& s = pipeline_->estimator().rollingRadii()[static_cast<std::size_t>(i)];
    stat.addf(config_.wheel_names[i] + " radius [m]", "%.5f", s.radius_m);
    stat.addf(config_.wheel_names[i] + " learned distance [m]", "%.1f", s.learned_distance_m);
  }
  if (!radius_save_error_.empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "save failed: " + radius_save_error_);
  else if (radius_restore_ == "invalid" || radius_restore_ == "rejected")
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "saved radii " + radius_restore_ + ": nominal radii");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "restore: " + radius_restore_);
}

}  // namespace tread_wear
