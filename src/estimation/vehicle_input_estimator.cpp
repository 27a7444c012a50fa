#include "tread_wear/estimation/vehicle_input_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Rolling resistance builds up over the first half metre per second, as vehicle_model.cpp [m/s].
constexpr double kRollingRampSpeed_mps = 0.5;
/// Saturation of the linear slip-ratio prior |Fx / C_kappa|, as vehicle_model.cpp [-].
constexpr double kMaxSlipUtilisation = 0.5;
/// Time constant of the fallback speed derivative (no IMU) [s].
constexpr double kSpeedDerivativeTimeConstant_s = 0.2;
/// Standard deviation of the zero-velocity update at standstill [m/s].
constexpr double kStandstillSigma_mps = 0.01;

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool nonNegative(double v) { return std::isfinite(v) && v >= 0.0; }
bool finite3(double a, double b, double c) { return std::isfinite(a) && std::isfinite(b) && std::isfinite(c); }
double lowPassGain(double dt_s, double tau_s) { return tau_s > 0.0 ? dt_s / (tau_s + dt_s) : 1.0; }

}  // namespace

const char* sensorName(Sensor sensor) {
  switch (sensor) {
    case Sensor::kImu: return "imu";
    case Sensor::kWheelSpeed: return "wheel_speed";
    case Sensor::kSteering: return "steering";
    case Sensor::kSpeed: return "speed";
  }
  return "unknown";
}

const char* sampleFaultName(SampleFault fault) {
  switch (fault) {
    case SampleFault::kNone: return "none";
    case SampleFault::kNotFinite: return "not_finite";
    case SampleFault::kOutOfOrder: return "out_of_order";
    case SampleFault::kOutOfRange: return "out_of_range";
    case SampleFault::kFrozen: return "frozen";
    case SampleFault::kStale: return "stale";
  }
  return "unknown";
}

const char* estimateQualityName(EstimateQuality quality) {
  switch (quality) {
    case EstimateQuality::kGood: return "good";
    case EstimateQuality::kDegraded: return "degraded";
    case EstimateQuality::kLowSpeed: return "low_speed";
    case EstimateQuality::kInvalid: return "invalid";
  }
  return "unknown";
}

const char* speedSourceName(SpeedSource source) {
  switch (source) {
    case SpeedSource::kNone: return "none";
    case SpeedSource::kWheels: return "wheels";
    case SpeedSource::kReferenceSpeed: return "reference_speed";
    case SpeedSource::kDeadReckoning: return "dead_reckoning";
  }
  return "unknown";
}

const char* yawRateSourceName(YawRateSource source) {
  switch (source) {
    case YawRateSource::kNone: return "none";
    case YawRateSource::kGyro: return "gyro";
    case YawRateSource::kWheelSpeeds: return "wheel_speeds";
    case YawRateSource::kSteeringModel: return "steering_model";
  }
  return "unknown";
}

const char* accelSourceName(AccelSource source) {
  switch (source) {
    case AccelSource::kNone: return "none";
    case AccelSource::kImu: return "imu";
    case AccelSource::kSpeedDerivative: return "speed_derivative";
  }
  return "unknown";
}

bool VehicleInputEstimatorParams::validate(std::string* error) const {
  if (!vehicle.validate(error)) {
    if (error != nullptr) *error = "vehicle." + *error;
    return false;
  }
  static const char* const kAxis[3] = {"0", "1", "2"};
  for (int k = 0; k < 3; ++k) {
    const std::string i = std::string("[") + kAxis[k] + "]";
    if (!(std::isfinite(imu_mount_rpy_rad[k]) && std::abs(imu_mount_rpy_rad[k]) <= M_PI))
      return failValidation(error, "imu_mount_rpy_rad" + i, imu_mount_rpy_rad[k], "finite and in [-pi, pi]");
    if (!std::isfinite(imu_position_m[k]))
      return failValidation(error, "imu_position_m" + i, imu_position_m[k], "finite");
    if (!std::isfinite(accel_bias_mps2[k]))
      return failValidation(error, "accel_bias_mps2" + i, accel_bias_mps2[k], "finite");
    if (!std::isfinite(gyro_bias_rps[k])) return failValidation(error, "gyro_bias_rps" + i, gyro_bias_rps[k], "finite");
  }
  if (!positive(gyro_bias_time_constant_s))
    return failValidation(error, "gyro_bias_time_constant_s", gyro_bias_time_constant_s, "finite and > 0");
  if (!nonNegative(load_filter_time_constant_s))
    return failValidation(error, "load_filter_time_constant_s", load_filter_time_constant_s, "finite and >= 0");
  if (!nonNegative(lateral_complement_time_constant_s))
    return failValidation(error, "lateral_complement_time_constant_s", lateral_complement_time_constant_s,
                          "finite and >= 0");
  if (!positive(steering_ratio)) return failValidation(error, "steering_ratio", steering_ratio, "finite and > 0");
  if (!std::isfinite(steering_offset_rad))
    return failValidation(error, "steering_offset_rad", steering_offset_rad, "finite");
  if (!(nonNegative(ackermann_share) && ackermann_share <= 1.0))
    return failValidation(error, "ackermann_share", ackermann_share, "in [0, 1]");
  for (int i = 0; i < kWheelCount; ++i)
    if (!positive(wheel_radius_m[static_cast<std::size_t>(i)]))
      return failValidation(error, std::string("wheel_radius_m[") + wheelName(i) + "]",
                            wheel_radius_m[static_cast<std::size_t>(i)], "finite and > 0");
  if (!nonNegative(wheel_speed_quantum_rps))
    return failValidation(error, "wheel_speed_quantum_rps", wheel_speed_quantum_rps, "finite and >= 0");
  if (!nonNegative(slip_prior_relative_sigma))
    return failValidation(error, "slip_prior_relative_sigma", slip_prior_relative_sigma, "finite and >= 0");
  if (!positive(slip_prior_sigma)) return failValidation(error, "slip_prior_sigma", slip_prior_sigma, "finite and > 0");
  if (!positive(radius_sigma_unconverged))
    return failValidation(error, "radius_sigma_unconverged", radius_sigma_unconverged, "finite and > 0");
  if (!positive(radius_sigma_converged))
    return failValidation(error, "radius_sigma_converged", radius_sigma_converged, "finite and > 0");
  if (!positive(wheel_gate)) return failValidation(error, "wheel_gate", wheel_gate, "> 0");
  if (!radius_learner.validate(error)) {
    if (error != nullptr) *error = "radius_learner." + *error;
    return false;
  }
  if (!nonNegative(speed_lag_s)) return failValidation(error, "speed_lag_s", speed_lag_s, "finite and >= 0");
  if (!positive(speed_sigma_mps)) return failValidation(error, "speed_sigma_mps", speed_sigma_mps, "finite and > 0");
  if (!observer.validate(error)) {
    if (error != nullptr) *error = "observer." + *error;
    return false;
  }
  if (!nonNegative(lateral_model_relative_sigma))
    return failValidation(error, "lateral_model_relative_sigma", lateral_model_relative_sigma, "finite and >= 0");
  if (!positive(lateral_model_sigma_mps))
    return failValidation(error, "lateral_model_sigma_mps", lateral_model_sigma_mps, "finite and > 0");
  if (!positive(imu_timeout_s)) return failValidation(error, "imu_timeout_s", imu_timeout_s, "finite and > 0");
  if (!positive(wheel_timeout_s)) return failValidation(error, "wheel_timeout_s", wheel_timeout_s, "finite and > 0");
  if (!positive(steering_timeout_s))
    return failValidation(error, "steering_timeout_s", steering_timeout_s, "finite and > 0");
  if (!positive(speed_timeout_s)) return failValidation(error, "speed_timeout_s", speed_timeout_s, "finite and > 0");
  if (!positive(frozen_wheel_time_s))
    return failValidation(error, "frozen_wheel_time_s", frozen_wheel_time_s, "finite and > 0");
  if (!positive(max_specific_force_mps2))
    return failValidation(error, "max_specific_force_mps2", max_specific_force_mps2, "finite and > 0");
  if (!positive(max_angular_rate_rps))
    return failValidation(error, "max_angular_rate_rps", max_angular_rate_rps, "finite and > 0");
  if (!positive(max_wheel_speed_rps))
    return failValidation(error, "max_wheel_speed_rps", max_wheel_speed_rps, "finite and > 0");
  if (!positive(max_steering_wheel_rad))
    return failValidation(error, "max_steering_wheel_rad", max_steering_wheel_rad, "finite and > 0");
  if (!positive(max_speed_mps)) return failValidation(error, "max_speed_mps", max_speed_mps, "finite and > 0");
  if (!positive(standstill_speed_mps))
    return failValidation(error, "standstill_speed_mps", standstill_speed_mps, "finite and > 0");
  if (!nonNegative(standstill_time_s))
    return failValidation(error, "standstill_time_s", standstill_time_s, "finite and >= 0");
  if (!(positive(min_slip_speed_mps) && min_slip_speed_mps > standstill_speed_mps))
    return failValidation(error, "min_slip_speed_mps", min_slip_speed_mps, "finite and > standstill_speed_mps");
  if (!positive(max_step_s)) return failValidation(error, "max_step_s", max_step_s, "finite and > 0");
  if (!nonNegative(max_dead_reckoning_s))
    return failValidation(error, "max_dead_reckoning_s", max_dead_reckoning_s, "finite and >= 0");
  return true;
}

namespace {
VehicleInputEstimatorParams checked(const VehicleInputEstimatorParams& params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid vehicle input estimator parameters: " + error);
  return params;
}
}  // namespace

VehicleInputEstimator::VehicleInputEstimator(const VehicleInputEstimatorParams& params)
    : params_(checked(params)), observer_(params_.observer), learner_(params_.radius_learner, params_.wheel_radius_m) {
  setImuMount(params_.imu_mount_rpy_rad, params_.imu_position_m);
  const VehicleParams& v = params_.vehicle;
  wheel_x_ = {v.cog_to_front_axle_m, v.cog_to_front_axle_m, -v.cogToRearAxle_m(), -v.cogToRearAxle_m()};
  wheel_y_ = {0.5 * v.track_front_m, -0.5 * v.track_front_m, 0.5 * v.track_rear_m, -0.5 * v.track_rear_m};
  gyro_bias_ = params_.gyro_bias_rps;
  wheel_used_stamp_.fill(-1e300);
  wheel_change_s_.fill(-1e300);
}

bool VehicleInputEstimator::setImuMount(const std::array<double, 3>& rpy, const std::array<double, 3>& position_m) {
  for (int k = 0; k < 3; ++k)
    if (!(std::isfinite(rpy[k]) && std::abs(rpy[k]) <= M_PI && std::isfinite(position_m[k]))) return false;
  params_.imu_mount_rpy_rad = rpy;
  params_.imu_position_m = position_m;
  const double cr = std::cos(rpy[0]), sr = std::sin(rpy[0]);
  const double cp = std::cos(rpy[1]), sp = std::sin(rpy[1]);
  const double cy = std::cos(rpy[2]), sy = std::sin(rpy[2]);
  // R_m = Rz(yaw) Ry(pitch) Rx(roll), row-major.
  mount_ = {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
            sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
            -sp,     cp * sr,                cp * cr};
  return true;
}

SampleFault VehicleInputEstimator::reject(Sensor sensor, SampleFault fault) {
  ++faults_[static_cast<int>(sensor)][static_cast<int>(fault)];
  return fault;
}

bool VehicleInputEstimator::fresh(const Stamped& s, double t_s, double timeout_s) const {
  return s.have && t_s - s.stamp_s <= timeout_s;
}

SampleFault VehicleInputEstimator::addImu(double t_s, double f_x, double f_y, double f_z, double w_x, double w_y,
                                          double w_z) {
  if (!std::isfinite(t_s) || !finite3(f_x, f_y, f_z) || !finite3(w_x, w_y, w_z))
    return reject(Sensor::kImu, SampleFault::kNotFinite);
  if (have_imu_ && !(t_s > imu_stamp_s_)) return reject(Sensor::kImu, SampleFault::kOutOfOrder);
  const double fmax = params_.max_specific_force_mps2, wmax = params_.max_angular_rate_rps;
  if (std::abs(f_x) > fmax || std::abs(f_y) > fmax || std::abs(f_z) > fmax || std::abs(w_x) > wmax ||
      std::abs(w_y) > wmax || std::abs(w_z) > wmax)
    return reject(Sensor::kImu, SampleFault::kOutOfRange);
  have_imu_ = true;
  imu_stamp_s_ = t_s;
  imu_f_ = {f_x, f_y, f_z};
  imu_w_ = {w_x, w_y, w_z};
  for (int k = 0; k < 3; ++k) {
    imu_f_sum_[k] += imu_f_[k];
    imu_w_sum_[k] += imu_w_[k];
  }
  ++imu_count_;
  return SampleFault::kNone;
}

SampleFault VehicleInputEstimator::addWheelSpeeds(double t_s, const std::array<double, kWheelCount>& omega_rps) {
  SampleFault first = SampleFault::kNone;
  std::array<SampleFault, kWheelCount> fault{};
  for (int i = 0; i < kWheelCount; ++i) {
    const double w = omega_rps[static_cast<std::size_t>(i)];
    const Stamped& s = wheel_[static_cast<std::size_t>(i)];
    if (!std::isfinite(t_s) || !std::isfinite(w)) {
      fault[i] = SampleFault::kNotFinite;
    } else if (s.have && !(t_s > s.stamp_s)) {
      fault[i] = SampleFault::kOutOfOrder;
    } else if (std::abs(w) > params_.max_wheel_speed_rps) {
      fault[i] = SampleFault::kOutOfRange;
    } else if (!s.have || w != s.value) {
      wheel_change_s_[static_cast<std::size_t>(i)] = t_s;
    }
  }
  // Frozen: unchanged for frozen_wheel_time_s while another wheel changed within half that time.
  for (int i = 0; i < kWheelCount; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    if (fault[i] == SampleFault::kNone && wheel_[ui].have &&
        t_s - wheel_change_s_[ui] > params_.frozen_wheel_time_s) {
      for (int j = 0; j < kWheelCount; ++j)
        if (j != i && fault[j] == SampleFault::kNone &&
            t_s - wheel_change_s_[static_cast<std::size_t>(j)] < 0.5 * params_.frozen_wheel_time_s)
          fault[i] = SampleFault::kFrozen;
    }
    wheel_frozen_[ui] = fault[i] == SampleFault::kFrozen || (wheel_frozen_[ui] && fault[i] != SampleFault::kNone);
    if (fault[i] != SampleFault::kNone) {
      reject(Sensor::kWheelSpeed, fault[i]);
      if (first == SampleFault::kNone) first = fault[i];
      continue;
    }
    wheel_[ui] = {true, t_s, omega_rps[ui]};
  }
  return first;
}

SampleFault VehicleInputEstimator::addSteering(double t_s, double angle_rad) {
  if (!std::isfinite(t_s) || !std::isfinite(angle_rad)) return reject(Sensor::kSteering, SampleFault::kNotFinite);
  if (steering_.have && !(t_s > steering_.stamp_s)) return reject(Sensor::kSteering, SampleFault::kOutOfOrder);
  if (std::abs(angle_rad) > params_.max_steering_wheel_rad) return reject(Sensor::kSteering, SampleFault::kOutOfRange);
  steering_ = {true, t_s, angle_rad};
  return SampleFault::kNone;
}

SampleFault VehicleInputEstimator::addSpeed(double t_s, double speed_mps) {
  if (!std::isfinite(t_s) || !std::isfinite(speed_mps)) return reject(Sensor::kSpeed, SampleFault::kNotFinite);
  if (speed_.have && !(t_s > speed_.stamp_s)) return reject(Sensor::kSpeed, SampleFault::kOutOfOrder);
  if (speed_mps < 0.0 || speed_mps > params_.max_speed_mps) return reject(Sensor::kSpeed, SampleFault::kOutOfRange);
  speed_ = {true, t_s, speed_mps};
  return SampleFault::kNone;
}

void VehicleInputEstimator::steerAngles(double delta, std::array<double, kWheelCount>* out) const {
  const VehicleParams& v = params_.vehicle;
  const double k = std::tan(delta) / v.wheelbase_m;  // curvature of the front axle centre about the rear axle
  const double half = 0.5 * v.track_front_m;
  const double left = std::atan(v.wheelbase_m * k / (1.0 - k * half));
  const double right = std::atan(v.wheelbase_m * k / (1.0 + k * half));
  const double a = params_.ackermann_share;
  (*out)[kFrontLeft] = delta + a * (left - delta);
  (*out)[kFrontRight] = delta + a * (right - delta);
  (*out)[kRearLeft] = 0.0;
  (*out)[kRearRight] = 0.0;
}

double VehicleInputEstimator::slipPrior(int wheel, double force_demand_n, double load_n, double ramp) const {
  const VehicleParams& p = params_.vehicle;
  if (!(load_n > 0.0)) return 0.0;
  double front_share = p.brake_balance_front;
  if (force_demand_n > 0.0) {
    front_share = p.drive_layout == DriveLayout::kFront ? 1.0
                  : p.drive_layout == DriveLayout::kRear ? 0.0
                                                         : p.all_wheel_front_drive_share;
  }
  const double share = 0.5 * (wheel < kRearLeft ? front_share : 1.0 - front_share);
  const double fx = share * force_demand_n - p.rolling_resistance_coefficient * load_n * ramp;
  const double u = std::clamp(fx / (p.longitudinal_slip_stiffness * load_n), -kMaxSlipUtilisation, kMaxSlipUtilisation);
  return u / (1.0 - u);
}

bool VehicleInputEstimator::estimate(double t_s, VehicleInputEstimate* out) {
  if (!std::isfinite(t_s) || (have_time_ && t_s < time_s_)) {
    ++clock_faults_;
    out->stamp_s = t_s;
    out->valid = false;
    return false;
  }
  Cycle& c = cycle_;
  c.t_s = t_s;
  c.dt = have_time_ ? t_s - time_s_ : 0.0;
  c.restart = !have_time_ || !observer_started_ || c.dt > params_.max_step_s;
  have_time_ = true;
  time_s_ = t_s;
  selectSensors(&c);
  bodyMotion(&c);
  yawRate(&c);
  directSpeed(&c);
  specificForce(&c);
  loads(&c);
  bool speed_measured = false;
  if (!c.restart) speed_measured = correctObserver(&c);
  if (speed_measured || c.restart) last_speed_measurement_s_ = t_s;
  writeVehicle(c, out);
  for (int i = 0; i < kWheelCount; ++i) writeWheel(c, i, out);
  return true;
}

void VehicleInputEstimator::selectSensors(Cycle* c) {
  const VehicleInputEstimatorParams& p = params_;
  const double t_s = c->t_s;
  c->imu_ok = have_imu_ && t_s - imu_stamp_s_ <= p.imu_timeout_s;
  if (have_imu_ && !c->imu_ok) ++faults_[static_cast<int>(Sensor::kImu)][static_cast<int>(SampleFault::kStale)];
  c->wheels_ok = 0;
  for (int i = 0; i < kWheelCount; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    c->wheel_ok[ui] = !wheel_frozen_[ui] && fresh(wheel_[ui], t_s, p.wheel_timeout_s);
    if (wheel_[ui].have && !wheel_frozen_[ui] && !c->wheel_ok[ui])
      ++faults_[static_cast<int>(Sensor::kWheelSpeed)][static_cast<int>(SampleFault::kStale)];
    c->wheels_ok += c->wheel_ok[ui] ? 1 : 0;
  }
  c->steer_ok = fresh(steering_, t_s, p.steering_timeout_s);
  if (steering_.have && !c->steer_ok)
    ++faults_[static_cast<int>(Sensor::kSteering)][static_cast<int>(SampleFault::kStale)];
  c->speed_ok = fresh(speed_, t_s, p.speed_timeout_s);
  if (speed_.have && !c->speed_ok) ++faults_[static_cast<int>(Sensor::kSpeed)][static_cast<int>(SampleFault::kStale)];
}

void VehicleInputEstimator::bodyMotion(Cycle* c) {
  const VehicleInputEstimatorParams& p = params_;
  // IMU: mean of the samples since the last cycle (or the last one held).
  std::array<double, 3> f_imu = imu_f_, w_imu = imu_w_;
  if (imu_count_ > 0) {
    for (int k = 0; k < 3; ++k) {
      f_imu[k] = imu_f_sum_[k] / imu_count_;
      w_imu[k] = imu_w_sum_[k] / imu_count_;
    }
  }
  imu_f_sum_ = {0.0, 0.0, 0.0};
  imu_w_sum_ = {0.0, 0.0, 0.0};
  imu_count_ = 0;

  // Standstill: every wheel fresh and below standstill_speed for standstill_time (or the reference speed).
  bool still_now = false;
  if (c->wheels_ok == kWheelCount) {
    still_now = true;
    for (int i = 0; i < kWheelCount; ++i)
      still_now = still_now && std::abs(wheel_[static_cast<std::size_t>(i)].value) * learner_.radius(i) <
                                   p.standstill_speed_mps;
  } else if (c->wheels_ok == 0 && c->speed_ok) {
    still_now = speed_.value < p.standstill_speed_mps;
  }
  if (still_now && !standstill_candidate_) standstill_since_s_ = c->t_s;
  standstill_candidate_ = still_now;
  c->standstill = still_now && c->t_s - standstill_since_s_ >= p.standstill_time_s;
  if (c->standstill && c->imu_ok && c->dt > 0.0) {
    const double a = lowPassGain(c->dt, p.gyro_bias_time_constant_s);
    for (int k = 0; k < 3; ++k) gyro_bias_[k] += a * (w_imu[k] - gyro_bias_[k]);
  }

  // Body-axis specific force and rates.
  c->f_b = {0.0, 0.0, 0.0};
  c->w_b = {0.0, 0.0, 0.0};
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) {
      c->f_b[r] += mount_[3 * r + k] * (f_imu[k] - p.accel_bias_mps2[k]);
      c->w_b[r] += mount_[3 * r + k] * (w_imu[k] - gyro_bias_[k]);
    }
  }
}

void VehicleInputEstimator::yawRate(Cycle* c) {
  const VehicleInputEstimatorParams& p = params_;
  const VehicleParams& vp = p.vehicle;
  const double g = vp.gravity_mps2, L = vp.wheelbase_m;
  const PlanarVelocityObserver::State& x0 = observer_.state();
  c->r = 0.0;
  c->yaw_source = YawRateSource::kNone;
  c->delta_mean = 0.0;
  if (c->steer_ok) c->delta_mean = (steering_.value - p.steering_offset_rad) / p.steering_ratio;
  if (c->imu_ok) {
    c->r = c->w_b[2];
    c->yaw_source = YawRateSource::kGyro;
  } else if (c->wheel_ok[kRearLeft] && c->wheel_ok[kRearRight]) {
    c->r = (wheel_[kRearRight].value * learner_.radius(kRearRight) -
            wheel_[kRearLeft].value * learner_.radius(kRearLeft)) /
           vp.track_rear_m;
    c->yaw_source = YawRateSource::kWheelSpeeds;
  } else if (c->steer_ok && observer_started_) {
    const double k_us =
        1.0 / (g * vp.cornering_stiffness_front_per_rad) - 1.0 / (g * vp.cornering_stiffness_rear_per_rad);
    c->r = x0(0) * c->delta_mean / (L + k_us * x0(0) * x0(0));
    c->yaw_source = YawRateSource::kSteeringModel;
  }
  if (c->dt > 0.0 && !c->restart)
    yaw_accel_ += lowPassGain(c->dt, p.load_filter_time_constant_s) * ((c->r - yaw_rate_prev_) / c->dt - yaw_accel_);
  yaw_rate_prev_ = c->r;
  steerAngles(c->delta_mean, &c->delta);
}

void VehicleInputEstimator::directSpeed(Cycle* c) {
  // Speed measured directly: the fallback derivative and the observer's start value.
  c->v_direct = 0.0;
  c->have_direct = false;
  if (c->wheels_ok > 0) {
    double sum = 0.0;
    for (int i = 0; i < kWheelCount; ++i)
      if (c->wheel_ok[static_cast<std::size_t>(i)])
        sum += wheel_[static_cast<std::size_t>(i)].value * learner_.radius(i) +
               c->r * wheel_y_[static_cast<std::size_t>(i)];
    c->v_direct = sum / c->wheels_ok;
    c->have_direct = true;
  } else if (c->speed_ok) {
    c->v_direct = speed_.value;
    c->have_direct = true;
  }
  if (c->have_direct && c->dt > 0.0 && !c->restart)
    speed_derivative_ += lowPassGain(c->dt, kSpeedDerivativeTimeConstant_s) *
                         ((c->v_direct - speed_prev_) / c->dt - speed_derivative_);
  if (c->have_direct) speed_prev_ = c->v_direct;
}

void VehicleInputEstimator::specificForce(Cycle* c) {
  const VehicleInputEstimatorParams& p = params_;
  const PlanarVelocityObserver::State& x0 = observer_.state();
  // At the CoG: the IMU with its lever arm, or the flat-road fallback.
  c->accel_source = AccelSource::kNone;
  c->f = {0.0, 0.0, 0.0};
  if (c->imu_ok) {
    const std::array<double, 3>& q = p.imu_position_m;
    const double r = c->r;
    c->f = {c->f_b[0] + yaw_accel_ * q[1] + r * r * q[0], c->f_b[1] - yaw_accel_ * q[0] + r * r * q[1], c->f_b[2]};
    c->accel_source = AccelSource::kImu;
  } else if (c->have_direct || observer_started_) {
    c->f = {speed_derivative_, x0(0) * c->r, p.vehicle.gravity_mps2};
    c->accel_source = AccelSource::kSpeedDerivative;
  }
  if (c->accel_source != AccelSource::kNone) {
    const double a = f_filtered_init_ && c->dt > 0.0 ? lowPassGain(c->dt, p.load_filter_time_constant_s) : 1.0;
    for (int k = 0; k < 3; ++k) f_filtered_[k] += a * (c->f[k] - f_filtered_[k]);
    f_filtered_init_ = true;
  }
  // Observer: restart or predict.
  if (c->restart) {
    observer_.reset(c->have_direct ? c->v_direct : 0.0, 0.0);
    observer_started_ = true;
  } else if (c->dt > 0.0 && c->accel_source != AccelSource::kNone) {
    observer_.predict(c->dt, c->f[0], c->f[1], c->r);
  }
}

void VehicleInputEstimator::loads(Cycle* c) {
  const VehicleInputEstimatorParams& p = params_;
  const VehicleParams& vp = p.vehicle;
  const double m = vp.mass_kg, g = vp.gravity_mps2, L = vp.wheelbase_m, h = vp.cog_height_m;
  const double l_f = vp.cog_to_front_axle_m, l_r = vp.cogToRearAxle_m();
  // Quasi-steady transfer from the filtered specific force (vehicle_model.h with f for a).
  const double v_pred = std::hypot(observer_.state()(0), observer_.state()(1));
  c->b_x = observer_.state()(2);
  c->b_y = observer_.state()(3);
  const double normal = c->imu_ok ? m * std::sqrt(std::max(0.0, g * g - c->b_x * c->b_x - c->b_y * c->b_y)) : m * g;
  const double f_aero = 0.5 * vp.air_density_kg_per_m3 * vp.drag_coefficient * vp.frontal_area_m2 * v_pred * v_pred;
  const double ramp = std::min(1.0, v_pred / kRollingRampSpeed_mps);
  // Lateral specific force: dynamics from the gyro (v_x r), the slow deviation (bank, bias, dv_y/dt) from the
  // accelerometer: f_y,c = v_x r + LP(f_y - v_x r).
  const double vx_pred = observer_.state()(0);
  if (c->accel_source != AccelSource::kNone) {
    const double a = lateral_init_ && c->dt > 0.0 ? lowPassGain(c->dt, p.lateral_complement_time_constant_s) : 1.0;
    lateral_deviation_ += a * (c->f[1] - vx_pred * c->r - lateral_deviation_);
    lateral_init_ = true;
  }
  c->fx_l = f_filtered_[0];
  c->fy_l = vx_pred * c->r + lateral_deviation_;
  const double dfz_long = (m * c->fx_l + f_aero) * h / L;
  const double fz_front = normal * l_r / L - dfz_long, fz_rear = normal * l_f / L + dfz_long;
  const double dfz_f = m * c->fy_l * h * vp.front_roll_stiffness_share / vp.track_front_m;
  const double dfz_r = m * c->fy_l * h * (1.0 - vp.front_roll_stiffness_share) / vp.track_rear_m;
  c->fz = {0.5 * fz_front - dfz_f, 0.5 * fz_front + dfz_f, 0.5 * fz_rear - dfz_r, 0.5 * fz_rear + dfz_r};
  for (double& load : c->fz) load = std::max(load, 0.0);
  const double demand = m * c->fx_l + f_aero + vp.rolling_resistance_coefficient * normal * ramp;
  for (int i = 0; i < kWheelCount; ++i)
    c->prior[static_cast<std::size_t>(i)] = slipPrior(i, demand, c->fz[static_cast<std::size_t>(i)], ramp);
  c->a_long = c->fx_l - c->b_x;  // kinematic longitudinal acceleration [m/s^2]
}

bool VehicleInputEstimator::correctObserver(Cycle* c) {
  bool speed_measured = correctWithWheels(*c);
  if (c->speed_ok) speed_measured = correctWithReferenceSpeed(*c) || speed_measured;
  correctWithLateralModel(*c, speed_measured);
  if (c->standstill) {
    const double var = kStandstillSigma_mps * kStandstillSigma_mps;
    const double inf = std::numeric_limits<double>::infinity();
    observer_.update(PlanarVelocityObserver::Row(1.0, 0.0, 0.0, 0.0), 0.0, 0.0, var, inf);
    observer_.update(PlanarVelocityObserver::Row(0.0, 1.0, 0.0, 0.0), 0.0, 0.0, var, inf);
    speed_measured = true;
  }
  return speed_measured;
}

bool VehicleInputEstimator::correctWithWheels(const Cycle& c) {
  const VehicleInputEstimatorParams& p = params_;
  bool speed_measured = false;
  for (int i = 0; i < kWheelCount; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    if (!c.wheel_ok[ui] || !(wheel_[ui].stamp_s > wheel_used_stamp_[ui])) continue;
    wheel_used_stamp_[ui] = wheel_[ui].stamp_s;
    const double R = learner_.radius(i);
    const double z = wheel_[ui].value * R / (1.0 + c.prior[ui]);
    PlanarVelocityObserver::Row hrow(std::cos(c.delta[ui]), std::sin(c.delta[ui]), 0.0, 0.0);
    const double offset = -c.r * wheel_y_[ui] * std::cos(c.delta[ui]) + c.r * wheel_x_[ui] * std::sin(c.delta[ui]);
    const double s_r = learner_.converged(i) ? p.radius_sigma_converged : p.radius_sigma_unconverged;
    const double q = p.wheel_speed_quantum_rps * R;
    const double s_k = p.slip_prior_relative_sigma * std::abs(c.prior[ui]) + p.slip_prior_sigma;
    const double var = q * q / 12.0 + z * z * (s_k * s_k + s_r * s_r) + 1e-8;
    if (observer_.update(hrow, offset, z, var, c.standstill ? std::numeric_limits<double>::infinity() : p.wheel_gate) <
        0.0)
      ++gated_wheel_updates_;
    else
      speed_measured = true;
  }
  return speed_measured;
}

bool VehicleInputEstimator::correctWithReferenceSpeed(const Cycle& c) {
  const VehicleInputEstimatorParams& p = params_;
  bool speed_measured = false;
  const double v_ref_now = speed_.value + c.a_long * (p.speed_lag_s + (c.t_s - speed_.stamp_s));
  if (speed_.stamp_s > speed_used_stamp_) {
    speed_used_stamp_ = speed_.stamp_s;
    observer_.update(PlanarVelocityObserver::Row(1.0, 0.0, 0.0, 0.0), 0.0, v_ref_now,
                     p.speed_sigma_mps * p.speed_sigma_mps, std::numeric_limits<double>::infinity());
    speed_measured = true;
  }
  // Rolling radii against the reference speed on free-rolling straights. a_long decides "free rolling" only
  // once the observer knows the grade offset b_x to better than the learner's acceleration gate: before that
  // (after a start or reset) an acceleration can hide in b_x, and the wheels' traction slip would be learned
  // as a smaller radius (seen on the comma2k19 RAV4 on-ramp, docs/real_car.md).
  const bool offset_settled = observer_.sigma(PlanarVelocityObserver::kBx) <= p.radius_learner.max_long_accel_mps2;
  if (c.dt > 0.0 && offset_settled) {
    for (int i = 0; i < kWheelCount; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      if (!c.wheel_ok[ui] || !c.steer_ok || !c.imu_ok) continue;
      const double ground = v_ref_now - c.r * wheel_y_[ui];
      learner_.addObservation(i, std::abs(ground) * c.dt, wheel_[ui].value, ground, c.a_long, c.r, c.delta[ui],
                              c.prior[ui]);
    }
  }
  return speed_measured;
}

void VehicleInputEstimator::correctWithLateralModel(const Cycle& c, bool speed_measured) {
  // Single-track lateral velocity (steady state, linear rear-axle cornering stiffness).
  const VehicleInputEstimatorParams& p = params_;
  const VehicleParams& vp = p.vehicle;
  const double vx = observer_.state()(0);
  const double fz_r = c.fz[kRearLeft] + c.fz[kRearRight];
  if (!(fz_r > 0.0 && (speed_measured || c.wheels_ok > 0 || c.speed_ok))) return;
  const double l_f = vp.cog_to_front_axle_m, l_r = vp.cogToRearAxle_m();
  double z = c.r * l_r, sigma = p.lateral_model_sigma_mps;
  if (std::abs(vx) >= p.min_slip_speed_mps) {
    const double alpha_r = -vp.mass_kg * c.fy_l * l_f / (vp.wheelbase_m * vp.cornering_stiffness_rear_per_rad * fz_r);
    const double vy_r = vx * std::tan(alpha_r);
    z += vy_r;
    sigma += p.lateral_model_relative_sigma * std::abs(vy_r);
  }
  observer_.update(PlanarVelocityObserver::Row(0.0, 1.0, 0.0, 0.0), 0.0, z, sigma * sigma,
                   std::numeric_limits<double>::infinity());
}

void VehicleInputEstimator::writeVehicle(const Cycle& c, VehicleInputEstimate* out) {
  const VehicleInputEstimatorParams& p = params_;
  const double g = p.vehicle.gravity_mps2;
  SpeedSource speed_source = SpeedSource::kNone;
  if (c.wheels_ok > 0)
    speed_source = SpeedSource::kWheels;
  else if (c.speed_ok)
    speed_source = SpeedSource::kReferenceSpeed;
  else if (c.imu_ok && c.t_s - last_speed_measurement_s_ <= p.max_dead_reckoning_s && observer_started_)
    speed_source = SpeedSource::kDeadReckoning;
  const PlanarVelocityObserver::State& x = observer_.state();
  const double vx = x(0), vy = x(1);
  const double v = std::hypot(vx, vy);
  const bool valid = speed_source != SpeedSource::kNone;
  const double r = c.r;
  out->stamp_s = c.t_s;
  out->valid = valid;
  out->speed_mps = valid ? v : kNaN;
  out->longitudinal_velocity_mps = valid ? vx : kNaN;
  out->lateral_velocity_mps = valid ? vy : kNaN;
  out->lateral_velocity_sigma_mps = observer_.sigma(PlanarVelocityObserver::kVy);
  out->sideslip_rad = valid && v >= p.min_slip_speed_mps ? std::atan2(vy, vx) : (valid ? 0.0 : kNaN);
  out->yaw_rate_rps = c.yaw_source != YawRateSource::kNone ? r : kNaN;
  out->path_curvature_per_m =
      valid && c.yaw_source != YawRateSource::kNone ? (v >= p.min_slip_speed_mps ? r / v : 0.0) : kNaN;
  out->long_specific_force_mps2 = c.fx_l;
  out->lat_specific_force_mps2 = c.fy_l;
  out->road_grade_rad = std::asin(std::clamp(c.b_x / g, -1.0, 1.0));
  out->road_bank_rad = std::asin(std::clamp(c.b_y / g, -1.0, 1.0));
  out->grade_sigma_rad = observer_.sigma(PlanarVelocityObserver::kBx) / g;
  out->bank_sigma_rad = observer_.sigma(PlanarVelocityObserver::kBy) / g;
  out->standstill = c.standstill;
  out->speed_source = speed_source;
  out->yaw_rate_source = c.yaw_source;
  out->accel_source = c.accel_source;
  out->steer_source = c.steer_ok ? SteerSource::kMeasured : SteerSource::kNone;
  out->sensor_fresh = {c.imu_ok, c.wheels_ok > 0, c.steer_ok, c.speed_ok};
}

void VehicleInputEstimator::writeWheel(const Cycle& c, int i, VehicleInputEstimate* out) const {
  const VehicleInputEstimatorParams& p = params_;
  const VehicleParams& vp = p.vehicle;
  const auto ui = static_cast<std::size_t>(i);
  WheelInputEstimate& w = out->wheels[ui];
  const bool front = i < kRearLeft;
  w.flags = 0;
  if (!c.wheel_ok[ui]) w.flags |= kFlagWheelSpeedMissing;
  if (wheel_frozen_[ui]) w.flags |= kFlagWheelFrozen;
  if (!learner_.converged(i)) w.flags |= kFlagRadiusNotConverged;
  if (!c.imu_ok) w.flags |= kFlagNoImu;
  w.rolling_radius_m = learner_.radius(i);
  w.steer_angle_rad = c.steer_ok ? c.delta[ui] : (front ? kNaN : 0.0);
  w.load_n = c.accel_source != AccelSource::kNone ? c.fz[ui] : kNaN;
  w.load_quality = c.accel_source == AccelSource::kImu    ? EstimateQuality::kGood
                   : c.accel_source == AccelSource::kNone ? EstimateQuality::kInvalid
                                                          : EstimateQuality::kDegraded;
  if (!out->valid || c.yaw_source == YawRateSource::kNone) {
    w.slip_angle_rad = w.slip_ratio = w.path_curvature_per_m = w.speed_mps = kNaN;
    w.slip_angle_quality = w.slip_ratio_quality = EstimateQuality::kInvalid;
    return;
  }
  const PlanarVelocityObserver::State& x = observer_.state();
  const double r = c.r;
  const double wvx = x(0) - r * wheel_y_[ui], wvy = x(1) + r * wheel_x_[ui];
  const double speed = std::hypot(wvx, wvy);
  w.speed_mps = speed;
  const bool slow = speed < p.min_slip_speed_mps;
  if (slow) w.flags |= kFlagLowSpeed;
  w.path_curvature_per_m = slow ? 0.0 : r / speed;
  const bool fallback = !(c.imu_ok && out->speed_source == SpeedSource::kWheels) || c.yaw_source != YawRateSource::kGyro;
  double alpha = 0.0;
  if (slow) {
    w.slip_angle_rad = 0.0;
    w.slip_angle_quality = EstimateQuality::kLowSpeed;
  } else if (front && !c.steer_ok) {
    const double fz_f = c.fz[kFrontLeft] + c.fz[kFrontRight];
    alpha = fz_f > 0.0 ? -vp.mass_kg * c.fy_l * vp.cogToRearAxle_m() /
                             (vp.wheelbase_m * vp.cornering_stiffness_front_per_rad * fz_f)
                       : 0.0;
    w.slip_angle_rad = alpha;
    w.slip_angle_quality = EstimateQuality::kDegraded;
    w.flags |= kFlagSteeringModel;
  } else {
    alpha = std::atan2(wvy, wvx) - c.delta[ui];
    w.slip_angle_rad = alpha;
    w.slip_angle_quality = fallback ? EstimateQuality::kDegraded : EstimateQuality::kGood;
  }
  if (slow) {
    w.slip_ratio = 0.0;
    w.slip_ratio_quality = EstimateQuality::kLowSpeed;
  } else if (!c.wheel_ok[ui]) {
    // No speed of its own: the slip of the wheel's quasi-steady force demand (drive layout, brake balance, slip
    // stiffness), the same prior that weighs its wheel-speed update when it has one.
    w.slip_ratio = c.prior[ui];
    w.slip_ratio_quality = EstimateQuality::kDegraded;
    w.flags |= kFlagSlipRatioFromForce;
  } else {
    w.slip_ratio = wheel_[ui].value * learner_.radius(i) / (speed * std::cos(alpha)) - 1.0;
    w.slip_ratio_quality = fallback || !learner_.converged(i) ? EstimateQuality::kDegraded : EstimateQuality::kGood;
  }
}

}  // namespace tread_wear
