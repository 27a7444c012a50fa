#pragma once
/// @file vehicle_input_estimator.h
/// Estimator of the wear model's per-wheel inputs (load, slip angle, slip ratio, path curvature, speed) from the
/// car's own sensors: IMU (specific force and angular rate), four wheel angular speeds, steering-wheel angle and
/// a reference vehicle speed (GNSS or odometry, possibly lagged). Free of ROS, time as double seconds; the
/// inverse of the quasi-steady forward model vehicle_model.h, with the same parameters and sign conventions
/// (ISO 8855: x forward, y left, z up; wheel order FL, FR, RL, RR). Equations and the measured error table:
/// docs/vehicle_inputs.md.
///
/// Two-phase API: addImu / addWheelSpeeds / addSteering / addSpeed validate and store samples (each with its
/// time stamp [s]); estimate(t, &out) advances to t and writes every output. A rejected sample is counted by
/// sensor and fault class (NaN/inf, out-of-order stamp, out of range, frozen wheel) and never used; a sensor whose
/// newest accepted sample is older than its timeout at estimate() is stale (counted per cycle) and not used.
///
/// Sensor model and corrections:
///   IMU      f_b = R_m (f_imu - b_a) - (r_dot x p + r x (r x p)),  w_b = R_m (w_imu - b_g)
///            R_m = Rz(yaw) Ry(pitch) Rx(roll) mount rotation IMU -> body, p lever arm from the CoG, b_a the
///            calibrated accelerometer bias, b_g the gyro bias (initial value, then averaged at standstill).
///            Samples between two estimate() calls are averaged. Yaw rate r = w_b,z.
///   steering mean front road-wheel angle delta = (delta_sw - delta_sw0) / i_s (steering ratio i_s); per wheel
///            Ackermann split about the rear axle: k = tan(delta)/L, delta_FL/FR,ideal = atan(L k / (1 -+ k t_f/2)),
///            delta_i = delta + A (delta_i,ideal - delta) (Ackermann share A in [0, 1]); rear wheels unsteered.
///   wheels   omega_i R_e,i = V_x,i (1 + kappa_i); R_e,i learned online (rolling_radius_learner.h) against the
///            reference speed on free-rolling straights.
///   speed    v_ref(t) = |v(t - tau)| (lag tau); used as v_ref + a_x tau.
/// Velocity: PlanarVelocityObserver (planar_velocity_observer.h), driven by f_b and r, corrected by
///   - each fresh wheel: z = omega_i R_e,i / (1 + kappa_prior,i) = (v_x - r y_i) cos delta_i + (v_y + r x_i) sin delta_i,
///     variance (omega quantum R/sqrt 12)^2 + (V (s_rel |kappa_prior| + s_0))^2 + (V s_R)^2 (s_R: radius
///     uncertainty, larger until the radius has converged), innovation gate chi^2 = wheel_gate;
///   - the reference speed: z = v_ref + a_x tau = v_x (v_y^2 neglected), variance speed_sigma^2;
///   - the single-track lateral velocity (steady state, linear axle cornering stiffness as vehicle_model.h):
///     alpha_r = -m f_y,c l_f / (L c_alpha,r Fz_r),  z = v_y = v_x tan(alpha_r) + r l_r,
///     variance (s_lat,rel |v_x tan alpha_r| + s_lat,0)^2; below min_slip_speed z = r l_r;
///   - at standstill (every wheel below standstill_speed for standstill_time): v_x = v_y = 0.
///   kappa_prior,i is the slip of the wheel's quasi-steady force demand, exactly as vehicle_model.h:
///   F = m f_x + F_aero + f_r N ramp(v), Fx_i = share_i F - f_r Fz_i ramp(v), u = Fx_i / (c_kappa Fz_i) clamped
///   to +-0.5, kappa_prior = u / (1 - u).
/// Specific force for loads and the lateral model: f_x, f_z low-passed (load_filter_time_constant_s); laterally
///   complementary, f_y,c = v_x r + LP_tau_y(f_y - v_x r): the dynamics from the gyro (less noise, no lag), the slow
///   deviation (bank, residual bias, steady dv_y/dt) from the accelerometer. Fast dv_y/dt (sideslip transients)
///   is filtered out of f_y,c: a limit in quick transients of a real car (the quasi-steady truth has none).
/// Loads (quasi-steady transfer of vehicle_model.h with the specific force for a, so a grade or bank enters
///   through gravity as the IMU measures it):
///   N = m sqrt(g^2 - b_x^2 - b_y^2) = m g cos(grade) cos(bank) (b from the observer; m g without IMU)
///   dFz_x = (m f_x + F_aero) h / L,  Fz_f = N l_r / L - dFz_x,  Fz_r = N l_f / L + dFz_x
///   dFz_f = m f_y,c h lambda_f / t_f,  dFz_r = m f_y,c h (1 - lambda_f) / t_r,  outer wheels gain, each clamped >= 0.
/// Slip angle  alpha_i = atan2(v_y + r x_i, v_x - r y_i) - delta_i  (x_i = l_f or -l_r, y_i = +-t/2)
/// Wheel speed V_i = |(v_x - r y_i, v_y + r x_i)|, wheel path curvature r / V_i, CoG curvature r / |v|.
/// Slip ratio  kappa_i = omega_i R_e,i / (V_i cos alpha_i) - 1.
/// Grade and bank: asin(b_x / g), asin(b_y / g), reported with their standard deviation; observable only while
/// the speed and the lateral model are measured (the residual accelerometer bias is part of them).
///
/// Fallbacks (named in the output; a quantity without a source is NaN with quality kInvalid, never a silent zero):
///   yaw rate       gyro -> rear-wheel speed difference (V_RR - V_RL)/t_r -> steady single track from steering
///                  r = v delta / (L + K_us v^2) -> none
///   specific force IMU -> derivative of the wheel/reference speed and f_y = v_x r on a flat road (loads degraded)
///   speed          wheels (+ IMU) -> reference speed -> IMU dead reckoning for max_dead_reckoning_s -> none
///   steering       measured -> front slip angles from the single-track model alpha_f = -m f_y,c l_r/(L c_f Fz_f)
///   slip ratio     the wheel's own speed (degraded while its radius has not converged) -> without it (missing,
///                  stale, rejected or frozen, one wheel or all four) kappa_prior,i, the slip of the wheel's
///                  quasi-steady force demand (drive layout, brake balance, slip stiffness; flag
///                  kFlagSlipRatioFromForce, quality kDegraded), so that wear goes on and says how it was estimated.
/// Below min_slip_speed a slip angle / slip ratio is undefined: value 0 with quality kLowSpeed.
/// Assumptions and limits: rigid body, quasi-steady load transfer (no pitch/roll dynamics, no roll-centre
/// heights, no aero lift); linear single-track cornering for the lateral pseudo-measurement (its error sets the
/// slip-angle error in transients); accelerometer bias and grade/bank not separable; reference speed needed to
/// learn rolling radii (without it they stay at the nominal values, flagged); the slip of the wheels that carry
/// the speed (undriven wheels while not braking) is close to its prior by construction.
/// Real time: no heap allocation after construction (add* and estimate), no logging; not thread-safe.

#include <array>
#include <cstdint>
#include <string>

#include "tread_wear/estimation/planar_velocity_observer.h"
#include "tread_wear/estimation/rolling_radius_learner.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

struct VehicleInputEstimatorParams {
  VehicleParams vehicle;  ///< mass, geometry, roll-stiffness share, resistances, stiffnesses (vehicle_model.h)

  // IMU
  std::array<double, 3> imu_mount_rpy_rad{{0.0, 0.0, 0.0}};  ///< mount rotation IMU -> body, roll/pitch/yaw [rad]
  std::array<double, 3> imu_position_m{{0.0, 0.0, 0.0}};     ///< IMU origin from the CoG, body axes [m]
  std::array<double, 3> accel_bias_mps2{{0.0, 0.0, 0.0}};    ///< calibrated accelerometer bias, IMU axes [m/s^2]
  std::array<double, 3> gyro_bias_rps{{0.0, 0.0, 0.0}};      ///< initial gyro bias, IMU axes [rad/s]
  double gyro_bias_time_constant_s = 1.0;    ///< averaging time of the gyro bias at standstill [s], > 0
  double load_filter_time_constant_s = 0.01; ///< low-pass of f_x, f_z for the loads [s], >= 0
  double lateral_complement_time_constant_s = 0.5;  ///< tau_y of f_y,c = v_x r + LP(f_y - v_x r) [s], >= 0

  // steering
  double steering_ratio = 15.0;          ///< i_s, steering-wheel angle per mean front road-wheel angle [-], > 0
  double steering_offset_rad = 0.0;      ///< steering-wheel angle when driving straight [rad]
  double ackermann_share = 1.0;          ///< A, 1 ideal Ackermann about the rear axle, 0 parallel [-], [0, 1]

  // wheels
  std::array<double, kWheelCount> wheel_radius_m{{0.31, 0.31, 0.31, 0.31}};  ///< nominal R_e [m], > 0
  double wheel_speed_quantum_rps = 0.02; ///< resolution of the wheel-speed signal [rad/s], >= 0
  double slip_prior_relative_sigma = 0.5;///< s_rel, uncertainty of kappa_prior as a share of it [-], >= 0
  double slip_prior_sigma = 5e-4;        ///< s_0, absolute uncertainty of kappa_prior [-], > 0
  double radius_sigma_unconverged = 0.01;///< s_R, relative radius uncertainty before convergence [-], > 0
  double radius_sigma_converged = 5e-4;  ///< s_R, relative radius uncertainty after convergence [-], > 0
  double wheel_gate = 25.0;              ///< chi^2 gate of a wheel-speed update (1 dof) [-], > 0
  RollingRadiusLearnerParams radius_learner;

  // reference speed
  double speed_lag_s = 0.0;              ///< tau, delay of the reference speed [s], >= 0
  double speed_sigma_mps = 0.05;         ///< its noise incl. lag-compensation error [m/s], > 0

  // observer
  PlanarObserverParams observer;
  double lateral_model_relative_sigma = 0.1;  ///< s_lat,rel, single-track v_y uncertainty share [-], >= 0
  double lateral_model_sigma_mps = 0.01;      ///< s_lat,0, single-track v_y uncertainty floor [m/s], > 0

  // timing, plausibility, conventions
  double imu_timeout_s = 0.05;           ///< IMU older than this is stale [s], > 0
  double wheel_timeout_s = 0.1;          ///< a wheel speed older than this is stale [s], > 0
  double steering_timeout_s = 0.2;       ///< steering older than this is stale [s], > 0
  double speed_timeout_s = 0.5;          ///< reference speed older than this is stale [s], > 0
  double frozen_wheel_time_s = 0.5;      ///< a wheel unchanged this long while another changes is frozen [s], > 0
  double max_specific_force_mps2 = 160.0;///< |f| above this is out of range [m/s^2], > 0
  double max_angular_rate_rps = 10.0;    ///< |w| above this is out of range [rad/s], > 0
  double max_wheel_speed_rps = 400.0;    ///< |omega| above this is out of range [rad/s], > 0
  double max_steering_wheel_rad = 12.0;  ///< |delta_sw| above this is out of range [rad], > 0
  double max_speed_mps = 100.0;          ///< reference speed above this (or < 0) is out of range [m/s], > 0
  double standstill_speed_mps = 0.05;    ///< every wheel's omega R below this: standing [m/s], > 0
  double standstill_time_s = 0.5;        ///< for at least this long [s], >= 0
  double min_slip_speed_mps = 2.0;       ///< slips undefined below this wheel speed [m/s], > 0
  double max_step_s = 0.5;               ///< an estimate() interval longer than this restarts the observer [s], > 0
  double max_dead_reckoning_s = 2.0;     ///< IMU-only speed for at most this long [s], >= 0

  /// Names field, value and broken constraint of the first invalid parameter.
  bool validate(std::string* error) const;
};

/// The estimator's inputs.
enum class Sensor : std::uint8_t { kImu = 0, kWheelSpeed = 1, kSteering = 2, kSpeed = 3 };
constexpr int kSensorCount = 4;
const char* sensorName(Sensor sensor);

/// Why a sample was rejected (or, kStale, why a sensor was not used at an estimate() cycle).
enum class SampleFault : std::uint8_t {
  kNone = 0,
  kNotFinite = 1,   ///< NaN or inf in a field
  kOutOfOrder = 2,  ///< stamp not after the sensor's (wheel's) last accepted stamp
  kOutOfRange = 3,  ///< beyond the plausibility limits of the params
  kFrozen = 4,      ///< wheel speed unchanged for frozen_wheel_time_s while another wheel changes
  kStale = 5        ///< counted per estimate() cycle: newest accepted sample older than the timeout
};
constexpr int kSampleFaultCount = 6;
const char* sampleFaultName(SampleFault fault);

/// Quality of one estimated quantity.
enum class EstimateQuality : std::uint8_t {
  kGood = 0,      ///< primary sources
  kDegraded = 1,  ///< a fallback is in use (see the source fields and flags)
  kLowSpeed = 2,  ///< slip undefined at this speed: value 0 by convention
  kInvalid = 3    ///< no source: value NaN
};
const char* estimateQualityName(EstimateQuality quality);

enum class SpeedSource : std::uint8_t { kNone = 0, kWheels = 1, kReferenceSpeed = 2, kDeadReckoning = 3 };
enum class YawRateSource : std::uint8_t { kNone = 0, kGyro = 1, kWheelSpeeds = 2, kSteeringModel = 3 };
enum class AccelSource : std::uint8_t { kNone = 0, kImu = 1, kSpeedDerivative = 2 };
enum class SteerSource : std::uint8_t { kNone = 0, kMeasured = 1 };
const char* speedSourceName(SpeedSource source);
const char* yawRateSourceName(YawRateSource source);
const char* accelSourceName(AccelSource source);

/// Per-wheel reasons (bit flags of WheelInputEstimate::flags).
enum WheelEstimateFlag : std::uint32_t {
  kFlagWheelSpeedMissing = 1u << 0,   ///< this wheel's speed is stale, rejected or never received
  kFlagWheelFrozen = 1u << 1,         ///< this wheel's speed is frozen
  kFlagRadiusNotConverged = 1u << 2,  ///< rolling radius still nominal / not yet learned over enough distance
  kFlagSteeringModel = 1u << 3,       ///< front slip angle from the single-track model (no steering)
  kFlagNoImu = 1u << 4,               ///< loads and lateral model on the flat-road fallback
  kFlagLowSpeed = 1u << 5,            ///< below min_slip_speed
  kFlagSlipRatioFromForce = 1u << 6   ///< slip ratio from the force demand (kappa_prior): no speed of its own
};

struct WheelInputEstimate {
  double load_n = 0.0;                ///< Fz [N]
  double slip_angle_rad = 0.0;        ///< alpha [rad], ISO
  double slip_ratio = 0.0;            ///< kappa [-], > 0 driving
  double path_curvature_per_m = 0.0;  ///< wheel path curvature [1/m], > 0 left
  double speed_mps = 0.0;             ///< wheel centre speed over the road V [m/s]
  double steer_angle_rad = 0.0;       ///< road-wheel steer angle delta_i used [rad]
  double rolling_radius_m = 0.0;      ///< R_e used [m]
  EstimateQuality load_quality = EstimateQuality::kInvalid;
  EstimateQuality slip_angle_quality = EstimateQuality::kInvalid;
  EstimateQuality slip_ratio_quality = EstimateQuality::kInvalid;
  std::uint32_t flags = 0;            ///< WheelEstimateFlag bits
};

struct VehicleInputEstimate {
  double stamp_s = 0.0;                 ///< [s]
  bool valid = false;                   ///< a speed source was available (else every quantity is kInvalid)
  std::array<WheelInputEstimate, kWheelCount> wheels;
  double speed_mps = 0.0;               ///< |v| of the CoG [m/s]
  double longitudinal_velocity_mps = 0.0;  ///< v_x [m/s]
  double lateral_velocity_mps = 0.0;    ///< v_y [m/s]
  double lateral_velocity_sigma_mps = 0.0;  ///< its standard deviation (observer covariance) [m/s]
  double sideslip_rad = 0.0;            ///< beta = atan2(v_y, v_x) [rad]
  double yaw_rate_rps = 0.0;            ///< r [rad/s]
  double path_curvature_per_m = 0.0;    ///< CoG path curvature r / |v| [1/m] (0 below min_slip_speed)
  double long_specific_force_mps2 = 0.0;///< filtered f_x at the CoG [m/s^2]
  double lat_specific_force_mps2 = 0.0; ///< filtered f_y at the CoG [m/s^2]
  double road_grade_rad = 0.0;          ///< asin(b_x/g), > 0 uphill [rad]
  double road_bank_rad = 0.0;           ///< asin(b_y/g), > 0 left side up [rad]
  double grade_sigma_rad = 0.0;         ///< standard deviation of the grade [rad]
  double bank_sigma_rad = 0.0;          ///< standard deviation of the bank [rad]
  bool standstill = false;              ///< zero-velocity update applied
  SpeedSource speed_source = SpeedSource::kNone;
  YawRateSource yaw_rate_source = YawRateSource::kNone;
  AccelSource accel_source = AccelSource::kNone;
  SteerSource steer_source = SteerSource::kNone;
  std::array<bool, kSensorCount> sensor_fresh{{false, false, false, false}};  ///< used at this cycle, by Sensor
};

class VehicleInputEstimator {
 public:
  /// @throw std::invalid_argument naming the field for invalid params
  explicit VehicleInputEstimator(const VehicleInputEstimatorParams& params);

  /// IMU sample in IMU axes: specific force f [m/s^2] and angular rate w [rad/s].
  SampleFault addImu(double t_s, double f_x_mps2, double f_y_mps2, double f_z_mps2, double w_x_rps, double w_y_rps,
                     double w_z_rps);
  /// Wheel angular speeds [rad/s] (>= 0 forward), order FL, FR, RL, RR; each wheel is checked on its own.
  /// Returns the first fault of the four (kNone when all were accepted).
  SampleFault addWheelSpeeds(double t_s, const std::array<double, kWheelCount>& omega_rps);
  /// Steering-wheel angle [rad], > 0 turning left.
  SampleFault addSteering(double t_s, double steering_wheel_angle_rad);
  /// Reference vehicle speed [m/s] (stamp = arrival; the signal lags by speed_lag_s).
  SampleFault addSpeed(double t_s, double speed_mps);

  /// Advances to t_s and writes the estimate. Returns false (out unchanged except stamp and valid = false when
  /// t_s goes backwards) for a backward or non-finite t_s, which is counted as clockFaults().
  bool estimate(double t_s, VehicleInputEstimate* out);

  /// Rejected samples (and stale cycles) by sensor and fault [-].
  std::uint64_t faultCount(Sensor sensor, SampleFault fault) const {
    return faults_[static_cast<int>(sensor)][static_cast<int>(fault)];
  }
  std::uint64_t clockFaults() const { return clock_faults_; }
  std::uint64_t gatedWheelUpdates() const { return gated_wheel_updates_; }

  /// A new IMU mount (imu_mount_rpy_rad, imu_position_m of the params), e.g. once its transform is known; the state
  /// goes on. false (unchanged) for a non-finite value or an angle outside [-pi, pi].
  bool setImuMount(const std::array<double, 3>& rpy_rad, const std::array<double, 3>& position_m);

  /// Rolling radii with their learned distance, to persist; restore at start-up (false: rejected, unchanged).
  const std::array<RollingRadiusState, kWheelCount>& rollingRadii() const { return learner_.state(); }
  bool restoreRollingRadii(const std::array<RollingRadiusState, kWheelCount>& state) { return learner_.restore(state); }
  bool radiusConverged(int wheel) const { return learner_.converged(wheel); }
  /// Current gyro bias, IMU axes [rad/s] (to persist with the radii).
  const std::array<double, 3>& gyroBias() const { return gyro_bias_; }

  const PlanarVelocityObserver& observer() const { return observer_; }
  const VehicleInputEstimatorParams& params() const { return params_; }

 private:
  struct Stamped {
    bool have = false;
    double stamp_s = -1e300;
    double value = 0.0;
  };
  /// One estimate() cycle's intermediate values, in the order its steps compute them (a member: no allocation).
  struct Cycle {
    double t_s = 0.0, dt = 0.0;  ///< cycle time and step [s]
    bool restart = false;        ///< the observer restarts at this cycle
    bool imu_ok = false, steer_ok = false, speed_ok = false;
    std::array<bool, kWheelCount> wheel_ok{};
    int wheels_ok = 0;
    bool standstill = false;
    std::array<double, 3> f_b{}, w_b{};  ///< body-axis specific force [m/s^2] and rates [rad/s] at the IMU
    double r = 0.0;                      ///< yaw rate [rad/s]
    YawRateSource yaw_source = YawRateSource::kNone;
    double delta_mean = 0.0;             ///< mean front road-wheel angle [rad]
    std::array<double, kWheelCount> delta{};  ///< road-wheel angles [rad]
    double v_direct = 0.0;               ///< speed from the wheels or the reference speed [m/s]
    bool have_direct = false;
    std::array<double, 3> f{};           ///< specific force at the CoG (IMU or flat-road fallback) [m/s^2]
    AccelSource accel_source = AccelSource::kNone;
    double fx_l = 0.0, fy_l = 0.0;       ///< filtered f_x and complementary f_y,c [m/s^2]
    double b_x = 0.0, b_y = 0.0;         ///< the observer's specific-force offsets (grade, bank) [m/s^2]
    double a_long = 0.0;                 ///< kinematic longitudinal acceleration [m/s^2]
    std::array<double, kWheelCount> fz{}, prior{};  ///< loads [N] and slip priors kappa_prior [-]
  };
  // The steps of estimate(), in order.
  void selectSensors(Cycle* c);    ///< which sensors are fresh (stale ones counted)
  void bodyMotion(Cycle* c);       ///< IMU mean, standstill and gyro bias, body-axis force and rates
  void yawRate(Cycle* c);          ///< yaw rate with its fallbacks, steer angles
  void directSpeed(Cycle* c);      ///< speed from wheels or reference, its derivative
  void specificForce(Cycle* c);    ///< force at the CoG, its filter, observer restart or prediction
  void loads(Cycle* c);            ///< load transfer and slip priors
  bool correctObserver(Cycle* c);  ///< every measurement update; true when a speed was measured
  bool correctWithWheels(const Cycle& c);
  bool correctWithReferenceSpeed(const Cycle& c);  ///< and the rolling-radius learning
  void correctWithLateralModel(const Cycle& c, bool speed_measured);
  void writeVehicle(const Cycle& c, VehicleInputEstimate* out);
  void writeWheel(const Cycle& c, int wheel, VehicleInputEstimate* out) const;

  SampleFault reject(Sensor sensor, SampleFault fault);
  bool fresh(const Stamped& s, double t_s, double timeout_s) const;
  void steerAngles(double delta_mean, std::array<double, kWheelCount>* delta) const;
  double slipPrior(int wheel, double force_demand_n, double load_n, double ramp) const;

  VehicleInputEstimatorParams params_;
  PlanarVelocityObserver observer_;
  RollingRadiusLearner learner_;
  std::array<double, 9> mount_{};  ///< R_m, row-major
  std::array<double, kWheelCount> wheel_x_{}, wheel_y_{};

  // latest accepted samples
  double imu_stamp_s_ = -1e300;
  bool have_imu_ = false;
  std::array<double, 3> imu_f_{}, imu_w_{};          ///< last accepted sample (IMU axes)
  std::array<double, 3> imu_f_sum_{}, imu_w_sum_{};  ///< sums since the last estimate()
  int imu_count_ = 0;
  std::array<Stamped, kWheelCount> wheel_{};
  std::array<double, kWheelCount> wheel_change_s_{};  ///< stamp at which each wheel's value last changed
  std::array<bool, kWheelCount> wheel_frozen_{};
  std::array<double, kWheelCount> wheel_used_stamp_{};
  Stamped steering_, speed_;
  double speed_used_stamp_ = -1e300;

  // filter state
  bool have_time_ = false;
  double time_s_ = 0.0;
  bool observer_started_ = false;
  std::array<double, 3> gyro_bias_{};
  std::array<double, 3> f_filtered_{};  ///< low-passed body specific force at the CoG [m/s^2]
  bool f_filtered_init_ = false;
  double lateral_deviation_ = 0.0;  ///< LP(f_y - v_x r) [m/s^2]
  bool lateral_init_ = false;
  double yaw_rate_prev_ = 0.0, yaw_accel_ = 0.0;
  double standstill_since_s_ = 0.0;
  bool standstill_candidate_ = false;
  double speed_prev_ = 0.0, speed_derivative_ = 0.0;  ///< fallback longitudinal acceleration
  double last_speed_measurement_s_ = -1e300;          ///< last time a wheel or reference speed corrected v

  std::array<std::array<std::uint64_t, kSampleFaultCount>, kSensorCount> faults_{};
  std::uint64_t clock_faults_ = 0, gated_wheel_updates_ = 0;
  Cycle cycle_;
};

}  // namespace tread_wear
