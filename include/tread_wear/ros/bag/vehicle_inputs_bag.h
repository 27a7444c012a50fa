#pragma once
/// @file vehicle_inputs_bag.h
/// The offline vehicle-inputs front end: a bag of the car's sensor topics (imu, joint_states, odom, and the IMU
/// mount base_link -> imu_link on /tf_static; the contract of docs/vehicle_inputs.md, as drive_bag_writer.h writes
/// it with --sensors) through VehicleInputPipeline (estimation/vehicle_input_pipeline.h) in input time, written
/// as the wear node's per-wheel inputs wheels/<name>/{load,slip,speed} into a new bag that tread_wear_replay
/// replays: what vehicle_inputs_node with the same configuration and input_time publishes when the bag is played to
/// it (test/ros/vehicle_inputs_bag.test). If the input bag also holds the true inputs (a generated drive), the
/// estimate is scored against them.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tread_wear/estimation/vehicle_input_pipeline.h"
#include "tread_wear/ros/bag/bag_check.h"

namespace tread_wear {

struct VehicleInputsOptions {
  VehicleInputsConfig config;  ///< the front end's configuration (io/vehicle_inputs_config.h): publish_rate_hz,
                               ///< joints, speed rule, wheel names (output topics wheels/<name>/...), estimator;
                               ///< the IMU mount comes from the bag's /tf_static
};

/// Error of one estimated quantity against the truth.
struct ErrorStat {
  double sum_sq = 0.0;
  double worst = 0.0;            ///< largest |error|
  std::size_t scored = 0;        ///< samples compared
  std::size_t skipped = 0;       ///< truth samples not scored (quality not kGood, or radius not converged)
  void add(double error);
  double rms() const;
  double scoredShare() const;
};

struct VehicleInputsResult {
  std::size_t imu_messages = 0, joint_state_messages = 0, odometry_messages = 0;
  std::size_t cycles = 0;                       ///< estimate() calls [-]
  std::size_t invalid_cycles = 0;               ///< of which without a speed source (nothing written)
  std::array<double, 3> imu_mount_rpy_rad{};    ///< from /tf_static [rad]
  std::array<double, 3> imu_position_m{};       ///< from /tf_static (base_link = CoG) [m]
  double odometry_lag_s = 0.0;                  ///< median record time - header stamp of odom [s] (reported: the
                                                ///< speed enters at its stamp, the estimator makes up the delay)
  std::array<RollingRadiusState, kWheelCount> radii{};  ///< learned at the end
  std::array<bool, kWheelCount> radius_converged{};
  std::uint64_t rejected_samples = 0;           ///< sum of the estimator's fault counters except kStale
  /// The estimator's counters by sensor and fault (kStale: cycles with that sensor stale).
  std::array<std::array<std::uint64_t, kSampleFaultCount>, kSensorCount> faults{};

  // Against the truth topics of the input bag (truth_present), per wheel:
  bool truth_present = false;
  std::array<ErrorStat, kWheelCount> load;        ///< [share of the static wheel load]
  std::array<ErrorStat, kWheelCount> slip_angle;  ///< [deg]
  std::array<ErrorStat, kWheelCount> slip_ratio;  ///< [-], only once the wheel's radius has converged
  std::array<ErrorStat, kWheelCount> speed;       ///< wheel speed [m/s]
};

/// Reads `in_path` (checkBagRecords first), feeds every sensor message in record order at its header stamp and runs
/// the cycles in input time (VehicleInputPipeline::cyclesBefore, through the last IMU or joint_states stamp), and
/// writes `out_path`: per wheel WheelLoad, WheelSlip, WheelSpeed at each cycle where the wheel is publishable (as the
/// node publishes; slips below the slip speed are 0 as the estimator gives them), plus the input's /drive/info if
/// any. Scores against wheels/<name>/{load,slip,speed} of the input bag at equal stamps when present: load and slip
/// angle when the estimate's quality is kGood, slip ratio when kGood (its radius has converged).
/// @throw BagError for an unreadable or corrupt bag, missing or mistyped sensor topics, no IMU mount on
///        /tf_static, or an unwritable output
VehicleInputsResult runVehicleInputs(const std::string& in_path, const std::string& out_path,
                                     const VehicleInputsOptions& options);

}  // namespace tread_wear
