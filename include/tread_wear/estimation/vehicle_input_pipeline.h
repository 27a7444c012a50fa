#pragma once
/// @file vehicle_input_pipeline.h
/// The vehicle-input front end, once, for every driver: vehicle_inputs_node (live topics) and
/// tread_wear_vehicle_inputs (a recorded bag) are thin drivers of VehicleInputPipeline, which holds what both do
/// between a sensor message and the per-wheel inputs of the wear node (docs/vehicle_inputs_node.md):
///   configuration  VehicleInputsConfig: joints, velocity signs, frames, speed source and rule, rates, the
///                  estimator's parameters; one defaults table, one validate(), read from the same YAML file by
///                  both (io/vehicle_inputs_config.h: the node through the parameter server, the tool from the file);
///   intake         every sample at its header stamp (never its arrival): IMU in its own axes with its mount in
///                  base_frame, joint states by name with their signs, the reference speed by the speed rule. In
///                  input time each is held for its cycle, so that the cycle it enters depends on its stamp, not on
///                  when it came: IMU and joint states until the first cycle at or after their stamp, the
///                  reference speed until the first at or after its stamp + input_delay_s;
///   fallbacks      VehicleInputEstimator's (estimation/vehicle_input_estimator.h), and a restart with the learned
///                  radii when the clock goes backwards;
///   the cycle      cycle(t) at a time the driver chooses (the node's timer), or in input time
///                  (cyclesBefore/cyclesThrough): on a grid of the publish period in the samples' own stamps, a cycle
///                  at t once every sample it takes has come: the IMU and the joint states each past t, the reference
///                  speed at or past t - input_delay_s (a stream silent for input_delay_s behind the others is not
///                  waited for). Input time depends on the data only, not on when or in which order the topics
///                  arrive, so that a bag played to the node and the same bag read by the tool give identical
///                  per-wheel inputs (test/ros/vehicle_inputs_bag.test);
///   the quality    per wheel: publishable or not, with the record of how each quantity was estimated.
///
/// Reference speed rule. The estimator takes the reference speed as the CoG's speed over ground, |v| = v_x with
/// v_y^2 neglected (vehicle_input_estimator.h). kPlanarNorm, hypot(v_x, v_y) of the message's twist, is the default
/// because it is that speed in any frame the twist is expressed in: nav_msgs/Odometry puts it in child_frame_id
/// (the body: then hypot differs from the longitudinal speed by v beta^2 / 2, 0.04 % at 1.6 deg of sideslip, below
/// the odometry noise), but GNSS drivers publish TwistWithCovarianceStamped in an east-north-up frame, where
/// |twist.linear.x| is the east component, wrong by the cosine of the heading (zero when driving north).
/// kLongitudinal, |v_x|, is right only for a body-frame twist and neglects nothing there; choose it for a
/// source whose lateral component is noise.
///
/// Threads: none of its own; not thread-safe (a driver calls it from one thread). Intake and the cycle allocate
/// nothing and never log (a restart rebuilds the estimator: it allocates).

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/estimation/vehicle_input_estimator.h"

namespace tread_wear {

/// How a reference-speed twist (v_x, v_y) becomes the estimator's speed.
enum class SpeedRule : std::uint8_t {
  kPlanarNorm = 0,    ///< hypot(v_x, v_y): the speed in whatever frame the twist is in (default)
  kLongitudinal = 1   ///< |v_x|: a twist in the body frame whose lateral component is not trusted
};
const char* speedRuleName(SpeedRule rule);
/// "planar_norm" / "longitudinal"; false for any other name.
bool parseSpeedRule(const std::string& name, SpeedRule* rule);
/// The rule applied: the speed [m/s] of a twist's linear (v_x, v_y) [m/s].
double referenceSpeed(SpeedRule rule, double v_x_mps, double v_y_mps);

/// Every setting of the front end (config/vehicle_inputs.yaml, docs/vehicle_inputs_node.md). The member
/// initialisers are the defaults of the node and the tool.
struct VehicleInputsConfig {
  double publish_rate_hz = 100.0;          ///< cycle and publication rate [Hz], (0, 1000]
  bool input_time = false;                 ///< node: cycles in the samples' stamps (input time) instead of on the
                                           ///< node's clock (the tool always runs in input time)
  std::string speed_source = "odom";       ///< reference speed: "odom" (nav_msgs/Odometry on `odom`) or "twist"
                                           ///< (geometry_msgs/TwistWithCovarianceStamped on `speed`)
  SpeedRule speed_rule = SpeedRule::kPlanarNorm;  ///< how its twist becomes a speed (see the file comment)
  double input_delay_s = 0.2;              ///< input time: the bound of a sample's delivery delay behind the newest
                                           ///< IMU or joint states [s], [0, 1]: a reference speed stamped s enters
                                           ///< the first cycle at or after s + this (odometry and GNSS come late),
                                           ///< and the cycles wait no longer than this for a silent stream
  std::string base_frame = "base_link";    ///< body frame (REP-103: x forward, y left, z up)
  std::array<double, 3> cog_position_m{{0.0, 0.0, 0.55}};  ///< CoG in base_frame [m] (default z = cog_height_m)
  bool cog_position_set = false;           ///< cog_position_m given (else z = the vehicle's h)
  std::array<std::string, kWheelCount> wheel_names{{"front_left", "front_right", "rear_left", "rear_right"}};
  std::array<std::string, kWheelCount> wheel_joints{
      {"wheel_front_left_joint", "wheel_front_right_joint", "wheel_rear_left_joint", "wheel_rear_right_joint"}};
  std::array<double, kWheelCount> wheel_velocity_signs{{1.0, 1.0, 1.0, 1.0}};  ///< joint velocity x sign = forward
                                           ///< wheel speed [-], each +1 or -1 (a mirrored joint axis: -1)
  bool use_wheel_speeds = true;            ///< false: the wheel joints' velocities are ignored (signals missing or
                                           ///< not trusted); slip ratios then come from the force demand
  std::array<std::string, kWheelCount> wheel_frames{
      {"wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right"}};  ///< for the rviz labels
  std::string steering_joint = "steering_wheel_joint";  ///< steering-wheel joint, position [rad], > 0 left
  double tf_timeout_s = 0.0;               ///< node: wait for a sensor transform in its callback [s], [0, 1]
  std::string vehicle_params_file;         ///< config/vehicle_*.yaml, required
  std::string radius_file;                 ///< node: learned rolling radii (JSON); empty = not persisted
  double save_interval_s = 30.0;           ///< node: period of radius saves (wall clock) [s], > 0
  double diagnostic_period_s = 1.0;        ///< node: /diagnostics period [s], > 0
  double marker_rate_hz = 5.0;             ///< node: rviz `vehicle_markers` rate [Hz], 0 = off, <= publish_rate_hz
  VehicleInputEstimatorParams estimator;   ///< vehicle part from vehicle_params_file, the rest under estimator/;
                                           ///< the IMU mount comes from the IMU's transform (setImuMount)

  /// Names the key, the value and the broken constraint of the first invalid setting.
  bool validate(std::string* error) const;
  /// Every value in use, one `key: value` a line (logged at start-up).
  std::string describe() const;
};

/// How one wheel's inputs were estimated at a cycle (the content of tread_wear/WheelInputQuality).
struct WheelInputQualityRecord {
  EstimateQuality load_quality = EstimateQuality::kInvalid;
  EstimateQuality slip_angle_quality = EstimateQuality::kInvalid;
  EstimateQuality slip_ratio_quality = EstimateQuality::kInvalid;
  std::uint32_t flags = 0;  ///< WheelEstimateFlag bits
  SpeedSource speed_source = SpeedSource::kNone;
  YawRateSource yaw_rate_source = YawRateSource::kNone;
  AccelSource accel_source = AccelSource::kNone;
  double steer_angle_rad = 0.0;   ///< road-wheel steer angle used [rad]
  double rolling_radius_m = 0.0;  ///< R_e used [m]
};
/// The record of one wheel (every quality kInvalid when the estimate as a whole is not valid).
WheelInputQualityRecord inputQuality(const VehicleInputEstimate& estimate, int wheel);
/// True when every quantity the wear node needs of this wheel has a source (load, slip angle, slip ratio valid
/// and finite, speed and curvature finite) and the estimate as a whole is valid.
bool wheelPublishable(const VehicleInputEstimate& estimate, int wheel);

/// The streams whose stamps drive the cycles in input time.
enum class InputStream : std::uint8_t { kImu = 0, kJoints = 1 };
constexpr int kInputStreamCount = 2;

/// What the intake saw, for diagnostics [-].
struct IntakeCounters {
  std::uint64_t imu = 0, imu_without_mount = 0;
  std::uint64_t joints = 0, joints_without_wheels = 0, joints_without_steering = 0;
  std::uint64_t speed = 0;
  std::uint64_t clock_faults = 0;  ///< cycles refused for a backward time (each restarts the estimator)
  std::uint64_t restarts = 0;      ///< estimator restarts after a backward clock
};

class VehicleInputPipeline {
 public:
  /// @throw std::invalid_argument naming the key for an invalid configuration
  explicit VehicleInputPipeline(const VehicleInputsConfig& config);

  const VehicleInputsConfig& config() const { return config_; }

  /// The IMU's mount in base_frame: rotation IMU -> base_frame (quaternion x, y, z, w) and the IMU origin [m]; the
  /// lever arm is origin - cog_position_m. The estimator goes on with its state (no sample is lost when the mount
  /// comes after the first samples). Without a mount the IMU is not used (counted), never taken as identity. false
  /// for a non-finite or zero quaternion or a non-finite origin (mount unchanged).
  bool setImuMount(const std::array<double, 4>& rotation_xyzw, const std::array<double, 3>& origin_m);
  bool imuMounted() const { return imu_mounted_; }

  /// Intake at header stamps [s] (the source's clock). IMU in its own axes: specific force [m/s^2], rate [rad/s].
  SampleFault addImu(double stamp_s, const std::array<double, 3>& specific_force_mps2,
                     const std::array<double, 3>& angular_rate_rps);
  /// A joint-states message: wheel velocities [rad/s] x their signs (a wheel joint absent enters as NaN: that
  /// wheel alone is rejected, never an old value in its place) and the steering-wheel position [rad].
  void addJoints(double stamp_s, const std::vector<std::string>& names, const std::vector<double>& position,
                 const std::vector<double>& velocity);
  /// A reference-speed twist, linear (v_x, v_y) [m/s], through the speed rule. In input time held for its cycle
  /// (kNone; a fault is counted by the estimator when it enters).
  SampleFault addSpeed(double stamp_s, double v_x_mps, double v_y_mps);

  /// The cycle on the driver's clock: estimates at t_s [s] (the source's clock). false for a backward or non-finite
  /// time: counted, and the next intake restarts the estimator with the learned radii.
  bool cycle(double t_s);
  /// Input time: a driver calls it before it hands over an IMU or joint-states sample stamped stamp_s [s]; every
  /// cycle of the grid that is then due runs (each stream past it), on_cycle(t_s) after each. A stamp more than
  /// max_step_s behind the last cycle (a looped bag) restarts the grid and the estimator.
  template <class OnCycle>
  void cyclesBefore(InputStream stream, double stamp_s, OnCycle&& on_cycle) {
    if (!startGrid(stream, stamp_s)) return;
    while (cycleDue(gridTime(next_cycle_))) runCycle(on_cycle);
  }
  /// Input time at the end of the data: every cycle up to and including stamp_s [s].
  template <class OnCycle>
  void cyclesThrough(double stamp_s, OnCycle&& on_cycle) {
    if (!grid_started_) return;
    while (gridTime(next_cycle_) <= stamp_s + kGridTolerance_s) runCycle(on_cycle);
  }

  /// The last cycle's estimate, its time [s] on the source's clock, and per wheel what a driver publishes.
  const VehicleInputEstimate& estimate() const { return estimate_; }
  double estimateTime_s() const { return estimate_time_s_; }
  bool publishable(int wheel) const { return wheelPublishable(estimate_, wheel); }
  WheelInputQualityRecord quality(int wheel) const { return inputQuality(estimate_, wheel); }

  const VehicleInputEstimator& estimator() const { return *estimator_; }
  /// Restores persisted rolling radii (false: rejected, unchanged).
  bool restoreRollingRadii(const std::array<RollingRadiusState, kWheelCount>& radii) {
    return estimator_->restoreRollingRadii(radii);
  }
  const IntakeCounters& counters() const { return counters_; }
  const std::array<double, 3>& imuLeverArm_m() const { return config_.estimator.imu_position_m; }

 private:
  static constexpr double kGridTolerance_s = 1e-7;
  double toEstimatorTime(double stamp_s);
  void rebuildEstimator();
  void restartIfPending();
  bool startGrid(InputStream stream, double stamp_s);
  /// Input time: every sample the cycle at t_s [s] takes has come: the IMU and the joint states each past t_s, the
  /// reference speed at or past t_s - input_delay_s (a stream silent for input_delay_s is not waited for).
  bool cycleDue(double t_s) const;
  template <class OnCycle>
  void runCycle(OnCycle&& on_cycle) {
    const double t = gridTime(next_cycle_++);
    releaseHeld(t);
    cycle(t);
    on_cycle(t);
  }
  /// Input time: into the estimator before the cycle at t_s, the held IMU and joint-states samples stamped at or
  /// before t_s and the reference speeds stamped at or before t_s - input_delay_s.
  void releaseHeld(double t_s);
  struct HeldImu {
    double stamp_s = 0.0;
    std::array<double, 3> f{}, w{};
  };
  struct HeldJoints {
    double stamp_s = 0.0;
    std::array<double, kWheelCount> omega{};
    bool wheels = false, steering = false;
    double steering_angle_rad = 0.0;
  };
  struct HeldSpeed {
    double stamp_s = 0.0, speed_mps = 0.0;
  };
  /// A fixed ring of samples held in input time (full: the oldest is handed on at once).
  template <class Sample, std::size_t N>
  struct Held {
    std::array<Sample, N> ring{};
    std::size_t first = 0, count = 0;
    bool full() const { return count == N; }
    const Sample& oldest() const { return ring[first]; }
    void push(const Sample& s) { ring[(first + count++) % N] = s; }
    void pop() {
      first = (first + 1) % N;
      --count;
    }
  };
  void applyImu(const HeldImu& s);
  void applyJoints(const HeldJoints& s);
  void applySpeed(const HeldSpeed& s);
  double gridTime(std::int64_t index) const { return static_cast<double>(index) / config_.publish_rate_hz; }

  VehicleInputsConfig config_;
  std::unique_ptr<VehicleInputEstimator> estimator_;
  VehicleInputEstimate estimate_;
  double estimate_time_s_ = 0.0;
  bool imu_mounted_ = false;
  bool have_epoch_ = false;
  double epoch_s_ = 0.0;  ///< estimator time = stamp - epoch (small times keep double precision) [s]
  bool restart_pending_ = false;
  bool grid_started_ = false;
  std::int64_t next_cycle_ = 0;  ///< input time: index of the next cycle on the grid k / publish_rate_hz
  double grid_start_s_ = 0.0;     ///< input time: stamp that started the grid [s]
  std::array<bool, kInputStreamCount> stream_seen_{};
  std::array<double, kInputStreamCount> stream_newest_s_{};  ///< input time: newest stamp per stream [s]
  bool speed_seen_ = false;
  double speed_newest_s_ = 0.0;   ///< input time: newest reference-speed stamp [s]
  Held<HeldImu, 512> held_imu_;        ///< input time: 0.5 s at 1 kHz
  Held<HeldJoints, 512> held_joints_;
  Held<HeldSpeed, 64> held_speeds_;
  std::vector<int> joint_index_;  ///< per name of the last joint-states layout: wheel 0..3, 4 steering, -1 none
  std::vector<std::string> joint_names_;  ///< that layout
  IntakeCounters counters_;
};

}  // namespace tread_wear
