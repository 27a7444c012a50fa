#include "tread_wear/estimation/vehicle_input_pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "tread_wear/vehicle/sensor_model.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// The estimator's clock starts this long before the first time seen, on a whole second [s].
constexpr double kEpochLead_s = 10.0;
/// The mount angles are taken to this step [rad], far below any calibration: a transform that went through tf2's
/// matrix form (the node) then gives the same estimator as the message's own quaternion (the tool).
constexpr double kMountAngleStep_rad = 1e-9;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

template <std::size_t N>
bool uniqueNonEmpty(const std::array<std::string, N>& names, const std::string& key, std::string* error) {
  std::set<std::string> seen;
  for (const std::string& n : names)
    if (n.empty() || !seen.insert(n).second) return fail(error, key + " = '" + n + "': must be non-empty and unique");
  return true;
}

VehicleInputsConfig checked(const VehicleInputsConfig& config) {
  std::string error;
  if (!config.validate(&error)) throw std::invalid_argument("invalid vehicle inputs configuration: " + error);
  return config;
}

}  // namespace

const char* speedRuleName(SpeedRule rule) {
  return rule == SpeedRule::kLongitudinal ? "longitudinal" : "planar_norm";
}

bool parseSpeedRule(const std::string& name, SpeedRule* rule) {
  if (name == "planar_norm") {
    *rule = SpeedRule::kPlanarNorm;
    return true;
  }
  if (name == "longitudinal") {
    *rule = SpeedRule::kLongitudinal;
    return true;
  }
  return false;
}

double referenceSpeed(SpeedRule rule, double v_x_mps, double v_y_mps) {
  return rule == SpeedRule::kLongitudinal ? std::fabs(v_x_mps) : std::hypot(v_x_mps, v_y_mps);
}

bool VehicleInputsConfig::validate(std::string* error) const {
  if (!(publish_rate_hz > 0.0 && publish_rate_hz <= 1000.0))
    return fail(error, "publish_rate_hz = " + number(publish_rate_hz) + ": must be in (0, 1000] [Hz]");
  if (speed_source != "odom" && speed_source != "twist")
    return fail(error, "speed_source = '" + speed_source + "': must be odom or twist");
  if (base_frame.empty()) return fail(error, "base_frame: must not be empty");
  for (double c : cog_position_m)
    if (!std::isfinite(c)) return fail(error, "cog_position_m: must be finite [m]");
  if (!uniqueNonEmpty(wheel_names, "wheel_names", error) || !uniqueNonEmpty(wheel_joints, "wheel_joints", error) ||
      !uniqueNonEmpty(wheel_frames, "wheel_frames", error))
    return false;
  for (double sign : wheel_velocity_signs)
    if (sign != 1.0 && sign != -1.0) return fail(error, "wheel_velocity_signs: " + number(sign) + ": each must be 1 or -1");
  if (steering_joint.empty()) return fail(error, "steering_joint: must not be empty");
  for (const std::string& j : wheel_joints)
    if (j == steering_joint)
      return fail(error, "steering_joint = '" + steering_joint + "': must differ from the wheel joints");
  if (!(input_delay_s >= 0.0 && input_delay_s <= 1.0))
    return fail(error, "input_delay_s = " + number(input_delay_s) + ": must be in [0, 1] [s]");
  if (!(tf_timeout_s >= 0.0 && tf_timeout_s <= 1.0))
    return fail(error, "tf_timeout_s = " + number(tf_timeout_s) + ": must be in [0, 1] [s]");
  if (!(save_interval_s > 0.0)) return fail(error, "save_interval_s = " + number(save_interval_s) + ": must be > 0 [s]");
  if (!(diagnostic_period_s > 0.0))
    return fail(error, "diagnostic_period_s = " + number(diagnostic_period_s) + ": must be > 0 [s]");
  if (!(marker_rate_hz >= 0.0 && marker_rate_hz <= publish_rate_hz))
    return fail(error, "marker_rate_hz = " + number(marker_rate_hz) + ": must be in [0, publish_rate_hz] [Hz]");
  std::string estimator_error;
  if (!estimator.validate(&estimator_error)) return fail(error, "estimator: " + estimator_error);
  return true;
}

std::string VehicleInputsConfig::describe() const {
  std::ostringstream s;
  s << "publish_rate_hz: " << publish_rate_hz << "\ninput_time: " << (input_time ? "true" : "false")
    << "\nspeed_source: " << speed_source << "\nspeed_rule: " << speedRuleName(speed_rule)
    << "\ninput_delay_s: " << input_delay_s
    << "\nbase_frame: " << base_frame << "\ncog_position_m: [" << cog_position_m[0] << ", " << cog_position_m[1]
    << ", " << cog_position_m[2] << "]\nuse_wheel_speeds: " << (use_wheel_speeds ? "true" : "false");
  for (int i = 0; i < kWheelCount; ++i)
    s << "\nwheel " << wheel_names[i] << ": joint " << wheel_joints[i] << " (sign " << wheel_velocity_signs[i]
      << "), frame " << wheel_frames[i];
  s << "\nsteering_joint: " << steering_joint << "\ntf_timeout_s: " << tf_timeout_s
    << "\nvehicle_params_file: " << vehicle_params_file << " (" << estimator.vehicle.name << ")"
    << "\nradius_file: " << (radius_file.empty() ? "(none)" : radius_file) << "\nsave_interval_s: " << save_interval_s
    << "\nmarker_rate_hz: " << marker_rate_hz;
  const VehicleInputEstimatorParams& e = estimator;
  s << "\nestimator/steering_ratio: " << e.steering_ratio << "\nestimator/steering_offset_rad: "
    << e.steering_offset_rad << "\nestimator/ackermann_share: " << e.ackermann_share << "\nestimator/wheel_radius_m: ["
    << e.wheel_radius_m[0] << ", " << e.wheel_radius_m[1] << ", " << e.wheel_radius_m[2] << ", " << e.wheel_radius_m[3]
    << "]\nestimator/speed_lag_s: " << e.speed_lag_s << "\nestimator/imu_timeout_s: " << e.imu_timeout_s
    << "\nestimator/wheel_timeout_s: " << e.wheel_timeout_s << "\nestimator/steering_timeout_s: "
    << e.steering_timeout_s << "\nestimator/speed_timeout_s: " << e.speed_timeout_s
    << "\nestimator/min_slip_speed_mps: " << e.min_slip_speed_mps;
  return s.str();
}

WheelInputQualityRecord inputQuality(const VehicleInputEstimate& e, int wheel) {
  const WheelInputEstimate& w = e.wheels[static_cast<std::size_t>(wheel)];
  WheelInputQualityRecord q;
  q.load_quality = e.valid ? w.load_quality : EstimateQuality::kInvalid;
  q.slip_angle_quality = e.valid ? w.slip_angle_quality : EstimateQuality::kInvalid;
  q.slip_ratio_quality = e.valid ? w.slip_ratio_quality : EstimateQuality::kInvalid;
  q.flags = w.flags;
  q.speed_source = e.speed_source;
  q.yaw_rate_source = e.yaw_rate_source;
  q.accel_source = e.accel_source;
  q.steer_angle_rad = w.steer_angle_rad;
  q.rolling_radius_m = w.rolling_radius_m;
  return q;
}

bool wheelPublishable(const VehicleInputEstimate& e, int wheel) {
  if (!e.valid) return false;
  const WheelInputEstimate& w = e.wheels[static_cast<std::size_t>(wheel)];
  return w.load_quality != EstimateQuality::kInvalid && w.slip_angle_quality != EstimateQuality::kInvalid &&
         w.slip_ratio_quality != EstimateQuality::kInvalid && std::isfinite(w.load_n) &&
         std::isfinite(w.slip_angle_rad) && std::isfinite(w.slip_ratio) && std::isfinite(w.path_curvature_per_m) &&
         std::isfinite(w.speed_mps);
}

VehicleInputPipeline::VehicleInputPipeline(const VehicleInputsConfig& config) : config_(checked(config)) {
  // The mount comes from the IMU's transform (setImuMount); until then the IMU is not used.
  config_.estimator.imu_mount_rpy_rad = {0.0, 0.0, 0.0};
  config_.estimator.imu_position_m = {0.0, 0.0, 0.0};
  estimator_ = std::make_unique<VehicleInputEstimator>(config_.estimator);
}

bool VehicleInputPipeline::setImuMount(const std::array<double, 4>& q, const std::array<double, 3>& origin_m) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(norm) || norm < 1e-6) return false;
  for (double c : origin_m)
    if (!std::isfinite(c)) return false;
  std::array<double, 3> rpy = SensorModel::rpyOf(q);
  for (double& angle : rpy) angle = std::round(angle / kMountAngleStep_rad) * kMountAngleStep_rad;
  const std::array<double, 3> lever{{origin_m[0] - config_.cog_position_m[0], origin_m[1] - config_.cog_position_m[1],
                                     origin_m[2] - config_.cog_position_m[2]}};
  if (!estimator_->setImuMount(rpy, lever)) return false;
  config_.estimator.imu_mount_rpy_rad = rpy;  // for a restart
  config_.estimator.imu_position_m = lever;
  imu_mounted_ = true;
  return true;
}

void VehicleInputPipeline::rebuildEstimator() {
  const std::array<RollingRadiusState, kWheelCount> radii = estimator_->rollingRadii();
  estimator_ = std::make_unique<VehicleInputEstimator>(config_.estimator);
  estimator_->restoreRollingRadii(radii);
}

void VehicleInputPipeline::restartIfPending() {
  if (!restart_pending_) return;
  restart_pending_ = false;
  ++counters_.restarts;
  rebuildEstimator();
}

double VehicleInputPipeline::toEstimatorTime(double stamp_s) {
  if (!have_epoch_) {
    epoch_s_ = stamp_s > kEpochLead_s ? std::floor(stamp_s) - kEpochLead_s : 0.0;
    have_epoch_ = true;
  }
  return stamp_s - epoch_s_;
}

SampleFault VehicleInputPipeline::addImu(double stamp_s, const std::array<double, 3>& f, const std::array<double, 3>& w) {
  restartIfPending();
  ++counters_.imu;
  toEstimatorTime(stamp_s);
  if (!imu_mounted_) {
    ++counters_.imu_without_mount;
    return SampleFault::kNone;
  }
  const HeldImu sample{stamp_s, f, w};
  if (!config_.input_time)
    return estimator_->addImu(toEstimatorTime(stamp_s), f[0], f[1], f[2], w[0], w[1], w[2]);
  if (held_imu_.full()) {
    applyImu(held_imu_.oldest());
    held_imu_.pop();
  }
  held_imu_.push(sample);
  return SampleFault::kNone;
}

void VehicleInputPipeline::applyImu(const HeldImu& s) {
  estimator_->addImu(toEstimatorTime(s.stamp_s), s.f[0], s.f[1], s.f[2], s.w[0], s.w[1], s.w[2]);
}

void VehicleInputPipeline::addJoints(double stamp_s, const std::vector<std::string>& names,
                                     const std::vector<double>& position, const std::vector<double>& velocity) {
  restartIfPending();
  ++counters_.joints;
  toEstimatorTime(stamp_s);
  if (names != joint_names_) {  // a new layout (the first message): allocates, once
    joint_names_ = names;
    joint_index_.assign(names.size(), -1);
    for (std::size_t k = 0; k < names.size(); ++k) {
      if (names[k] == config_.steering_joint) joint_index_[k] = kWheelCount;
      for (int i = 0; i < kWheelCount; ++i)
        if (names[k] == config_.wheel_joints[static_cast<std::size_t>(i)]) joint_index_[k] = i;
    }
  }
  HeldJoints sample;
  sample.stamp_s = stamp_s;
  sample.omega.fill(kNaN);
  int found = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const int i = joint_index_[k];
    if (i == kWheelCount && k < position.size()) {
      sample.steering = true;
      sample.steering_angle_rad = position[k];
    } else if (i >= 0 && i < kWheelCount && k < velocity.size()) {
      sample.omega[static_cast<std::size_t>(i)] =
          config_.wheel_velocity_signs[static_cast<std::size_t>(i)] * velocity[k];
      ++found;
    }
  }
  if (found < kWheelCount) ++counters_.joints_without_wheels;
  if (!sample.steering) ++counters_.joints_without_steering;
  sample.wheels = found > 0 && config_.use_wheel_speeds;
  if (!config_.input_time) {
    applyJoints(sample);
    return;
  }
  if (held_joints_.full()) {
    applyJoints(held_joints_.oldest());
    held_joints_.pop();
  }
  held_joints_.push(sample);
}

void VehicleInputPipeline::applyJoints(const HeldJoints& s) {
  const double t = toEstimatorTime(s.stamp_s);
  if (s.wheels) estimator_->addWheelSpeeds(t, s.omega);
  if (s.steering) estimator_->addSteering(t, s.steering_angle_rad);
}

SampleFault VehicleInputPipeline::addSpeed(double stamp_s, double v_x_mps, double v_y_mps) {
  restartIfPending();
  ++counters_.speed;
  toEstimatorTime(stamp_s);
  const HeldSpeed sample{stamp_s, referenceSpeed(config_.speed_rule, v_x_mps, v_y_mps)};
  if (!config_.input_time) return estimator_->addSpeed(toEstimatorTime(stamp_s), sample.speed_mps);
  speed_newest_s_ = speed_seen_ ? std::max(speed_newest_s_, stamp_s) : stamp_s;
  speed_seen_ = true;
  if (held_speeds_.full()) {
    applySpeed(held_speeds_.oldest());
    held_speeds_.pop();
  }
  held_speeds_.push(sample);
  return SampleFault::kNone;
}

void VehicleInputPipeline::applySpeed(const HeldSpeed& s) {
  estimator_->addSpeed(toEstimatorTime(s.stamp_s), s.speed_mps);
}

void VehicleInputPipeline::releaseHeld(double t_s) {
  const double due_s = t_s + kGridTolerance_s;
  for (; held_imu_.count > 0 && held_imu_.oldest().stamp_s <= due_s; held_imu_.pop()) applyImu(held_imu_.oldest());
  for (; held_joints_.count > 0 && held_joints_.oldest().stamp_s <= due_s; held_joints_.pop())
    applyJoints(held_joints_.oldest());
  for (; held_speeds_.count > 0 && held_speeds_.oldest().stamp_s + config_.input_delay_s <= due_s; held_speeds_.pop())
    applySpeed(held_speeds_.oldest());
}

bool VehicleInputPipeline::cycle(double t_s) {
  estimate_time_s_ = t_s;
  if (!estimator_->estimate(toEstimatorTime(t_s), &estimate_)) {
    // The clock went backwards (a looped bag, a sim-time reset): the next intake restarts the estimator.
    ++counters_.clock_faults;
    restart_pending_ = true;
    return false;
  }
  return true;
}

bool VehicleInputPipeline::startGrid(InputStream stream, double stamp_s) {
  if (!std::isfinite(stamp_s)) return false;
  if (grid_started_ && stamp_s < gridTime(next_cycle_ - 1) - config_.estimator.max_step_s) {
    grid_started_ = false;  // a looped bag: a new grid, and a new estimator with the learned radii
    held_imu_.count = held_joints_.count = held_speeds_.count = 0;
    stream_seen_.fill(false);
    speed_seen_ = false;
    restart_pending_ = true;
    restartIfPending();
  }
  toEstimatorTime(stamp_s);  // the epoch from the first stamp that starts a grid, if none before
  if (!grid_started_) {
    next_cycle_ = static_cast<std::int64_t>(std::ceil(stamp_s * config_.publish_rate_hz - 1e-6));
    grid_start_s_ = stamp_s;
    grid_started_ = true;
  }
  const auto s = static_cast<std::size_t>(stream);
  stream_newest_s_[s] = stream_seen_[s] ? std::max(stream_newest_s_[s], stamp_s) : stamp_s;
  stream_seen_[s] = true;
  return true;
}

bool VehicleInputPipeline::cycleDue(double t_s) const {
  // A stream not seen yet counts as at the grid's start: it is waited for as long as a silent one.
  double newest = grid_start_s_;
  for (int s = 0; s < kInputStreamCount; ++s)
    if (stream_seen_[static_cast<std::size_t>(s)]) newest = std::max(newest, stream_newest_s_[static_cast<std::size_t>(s)]);
  const double live_s = newest - config_.input_delay_s;  // a stream behind this is silent
  for (int s = 0; s < kInputStreamCount; ++s) {
    const auto us = static_cast<std::size_t>(s);
    const double stream_s = stream_seen_[us] ? stream_newest_s_[us] : grid_start_s_;
    if (stream_s >= live_s && t_s >= stream_s - kGridTolerance_s) return false;  // its samples at t_s may follow
  }
  // The reference speed: every sample up to t_s - input_delay_s has come once one stamped there has (one not seen
  // yet might be stamped at the grid's start).
  if (!speed_seen_) {
    const double first_due_s = grid_start_s_ + config_.input_delay_s;
    return !(first_due_s >= live_s && t_s >= first_due_s - kGridTolerance_s);
  }
  const double speed_s = speed_newest_s_ + config_.input_delay_s;
  return !(speed_s >= live_s && t_s > speed_s + kGridTolerance_s);
}

}  // namespace tread_wear
