#pragma once
/// @file drive_replay.h
/// Offline replay of a recorded drive through the same per-wheel estimator as the live node
/// (wheel_estimator.h), far faster than real time. ROS-free: the bag layer (readDriveBag,
/// src/ros/bag/drive_bag_reader.cpp, for tread_wear_replay in src/ros/bag/replay_cli.cpp) feeds samples.
///
/// Sampling: every input sample is applied to the wheel's WheelInputs at its time (the bag's record time; the drive
/// bags of tread_wear_drive stamp the headers with the same time); a fixed-rate loop at update_rate_hz steps each
/// wheel's WheelEstimator at t_k = t_0 + k / rate, t_0 = the first sample time of the drive, after applying every
/// sample with time <= t_k. tread_wear_node under simulated time steps each wheel on the same kind of grid in its
/// inputs' header stamps (WheelPipeline::receive, InputTimeline); test/ros/fast_replay.test holds the node's loss
/// per wheel equal to this replay's within 0.5% on a 300 s WLTC bag.
/// Wheels are independent, so each wheel runs in its own thread (up to `threads`); results do not depend on it.
///
/// Summary (ReplaySummary): per wheel the accumulated loss [kg], distance [m], mg/km, means of the stick and
/// slide fractions over evaluated steps, the time not integrated, and the loss per drive phase (each
/// interval's loss goes to the phase of its end time).

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

/// Estimation settings shared by all wheels (the node's config keys of the same names).
struct ReplaySettings {
  double update_rate_hz = 100.0;   ///< fixed step rate [Hz], > 0
  WearModelOptions model;          ///< preset, turn-slip orientation, low-speed threshold
  WheelEstimatorParams estimator;  ///< staleness, time jumps, input limits
  int threads = 2;                 ///< worker threads (one wheel per thread at a time), >= 1
  /// Longest bag time span replayed [s], > 0. Every wheel's step records are allocated for the whole span (6 h at
  /// 100 Hz: about 1 GB for 4 wheels), so one corrupt time stamp must not ask for terabytes: run() refuses a
  /// longer span with an error that names the largest gap between a wheel's samples.
  double max_span_s = 6.0 * 3600.0;

  bool validate(std::string* error) const;
};

struct ReplayWheel {
  std::string name;      ///< wheel name (topic wheels/<name>/...)
  std::string frame_id;  ///< frame of its output messages
  std::string tire_id;   ///< tire id of its output messages
  TireParams tire;
};

/// What one step of one wheel produced (the fields of WheelWear).
struct StepRecord {
  double wear_rate_kg_per_m, wear_rate_kg_per_s, accumulated_loss_kg, tread_depth_loss_m, remaining_tread_depth_m;
  double distance_m, stick_fraction, slide_fraction, exact_stick_fraction, fx_n, fy_n, mz_nm, unaccounted_time_s;
  double speed_mps;  ///< input speed used at this step [m/s] (0 when not evaluated)
  /// Friction-work rate of the step's forces on the rigid slip velocities, |Fx| |kappa V_x| + |Fy| |V sin(alpha)|
  /// [W] (0 when not evaluated): the friction-work wear models' quantity (docs/measured_road_wear.md)
  double friction_power_w;
  WheelStatus status;
  Preset preset;
  bool evaluated;
  bool integrated;  ///< the interval ending at this step was integrated
};

struct WheelSummary {
  std::string name;
  double mass_loss_kg = 0.0, distance_m = 0.0, mg_per_km = 0.0;
  double stick_fraction_mean = 0.0, slide_fraction_mean = 0.0;  ///< over evaluated steps [-]
  double friction_work_j = 0.0;  ///< friction_power_w integrated over the integrated intervals (trapezoid) [J]
  double unaccounted_time_s = 0.0;
  std::uint64_t samples_received = 0, samples_rejected = 0, evaluations = 0, time_jumps = 0;
  std::vector<double> phase_loss_kg;  ///< per phase of ReplaySummary::phases [kg]
};

struct ReplaySummary {
  double start_s = 0.0, end_s = 0.0;  ///< replayed time span [s]
  double phase_time_offset_s = 0.0;   ///< replay time of drive time 0 [s]
  std::uint64_t steps = 0;
  std::vector<ProfilePhase> phases;
  std::vector<double> phase_distance_m;  ///< mean wheel distance per phase [m]
  std::vector<WheelSummary> wheels;
  double wall_time_s = 0.0;  ///< replay compute time [s]
  bool complete = false;     ///< all required inputs of all wheels present and >= 99% of the time integrated
  std::string incomplete_reason;
};

class DriveReplay {
 public:
  /// @throw std::invalid_argument for invalid settings, tire parameters or no wheels
  DriveReplay(const ReplaySettings& settings, std::vector<ReplayWheel> wheels);
  ~DriveReplay();

  /// Appends a sample; samples of one wheel must come in non-decreasing time.
  void addSample(int wheel, const InputSample& sample);
  int wheelCount() const { return static_cast<int>(wheels_.size()); }
  const ReplayWheel& wheel(int i) const { return wheels_[static_cast<std::size_t>(i)]; }
  std::size_t sampleCount(int wheel) const;

  /// Runs all steps. progress (optional) counts finished wheel-steps, out of steps() * wheelCount().
  /// @throw std::runtime_error when the samples span more than max_span_s; an exception of a wheel's thread is
  /// rethrown here once every thread has finished
  void run(std::atomic<std::uint64_t>* progress = nullptr);
  std::uint64_t steps() const;
  double stepTime(std::uint64_t k) const { return t0_ + static_cast<double>(k) / settings_.update_rate_hz; }
  const std::vector<StepRecord>& records(int wheel) const;

  /// Summary of a finished run; phases (may be empty, in drive time) attribute the loss to drive phases;
  /// drive time = replay time - phase_time_offset_s.
  ReplaySummary summarize(const std::vector<ProfilePhase>& phases, double phase_time_offset_s = 0.0) const;
  const ReplaySettings& settings() const { return settings_; }

 private:
  struct WheelRun;
  void runWheel(int wheel, std::atomic<std::uint64_t>* progress);

  ReplaySettings settings_;
  std::vector<ReplayWheel> wheels_;
  std::vector<std::unique_ptr<WheelRun>> runs_;
  double t0_ = 0.0, t_end_ = 0.0;
  double wall_time_s_ = 0.0;
};

}  // namespace tread_wear
