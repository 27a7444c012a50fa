#pragma once
/// @file wheel_estimator.h
/// Per-wheel live wear estimation, free of ROS, shared by the node (src/ros) and the offline replay so both
/// produce the same numbers from the same inputs.
///
/// Two parts, in the pattern of robot_localization's filter core and diff_drive_controller's update loop:
///   WheelInputs     the latest accepted sample of each input (load, slip, speed, optional tread temperature)
///                   with its arrival time. Every sample is validated on arrival: a rejected sample is counted
///                   by its fault class and invalidates that input until a valid one arrives, so bad data
///                   never reach the model (it is neither used nor silently replaced by an older value).
///   WheelEstimator  a fixed-rate step(now) that samples WheelInputs, drops stale inputs, evaluates the wear
///                   model and integrates accumulated mass loss and distance over the actual elapsed time.
///
/// Integration (trapezoid rule over the actual elapsed time between consecutive steps):
///   loss     += 0.5 (wdot_prev + wdot_now) dt      wdot = wear per time [kg/s] (W_r V, WearModel convention)
///   distance += 0.5 (V_prev + V_now) dt
/// Only intervals whose both ends were evaluated from fresh, valid inputs are integrated. An interval that
/// starts or ends without usable inputs (stale, invalid, missing) or spans a time jump is not integrated; its
/// length is added to unaccountedTime_s() so a user sees how much of the drive the estimate does not cover, and
/// to unaccountedTime_s(cause) under the reason the interval was lost; integratedTime_s() is the rest, so a reader
/// that samples both (the node's diagnostics) knows the share lost between two of its samples.
/// The accumulated loss therefore never decreases and never absorbs a wrong time step.
///
/// Time jumps: dt < 0 (a looping bag, a simulation time reset) or dt > max_step_s (a pause, a clock jump) are counted
/// and the step restarts the integration from the new time without touching the accumulated state.
///
/// Equivalent tread depth: d = loss / (rho w 2 pi R) (MaterialParams::massPerDepth_kg_per_m), the depth of a
/// uniform tread layer of density rho, width w and radius R that has the accumulated mass.
///
/// Real time: no allocation after construction; step() evaluates the model once. Not thread-safe: the node
/// guards WheelInputs with its own lock and copies it before step().

#include <array>
#include <cstdint>
#include <string>

#include "tread_wear/model/wear_model.h"

namespace tread_wear {

/// The inputs of one wheel.
enum class InputKind : std::uint8_t { kLoad = 0, kSlip = 1, kSpeed = 2, kTemperature = 3 };
constexpr int kInputKindCount = 4;
const char* inputKindName(InputKind kind);

/// Why an input sample was rejected.
enum class InputFault : std::uint8_t {
  kNone = 0,
  kNotFinite = 1,             ///< NaN or +-inf in any field
  kNegativeLoad = 2,          ///< Fz < 0
  kLoadTooLarge = 3,          ///< Fz > InputLimits::max_load_n
  kSlipAngleOutOfRange = 4,   ///< |alpha| > InputLimits::max_abs_slip_angle_rad
  kSlipRatioOutOfRange = 5,   ///< kappa outside [-max, max] or kappa <= -1
  kCurvatureOutOfRange = 6,   ///< |1/R| > InputLimits::max_abs_path_curvature_per_m
  kNegativeSpeed = 7,         ///< V < 0
  kSpeedTooLarge = 8,         ///< V > InputLimits::max_speed_mps
  kTemperatureOutOfRange = 9  ///< T outside [min_temperature_c, max_temperature_c]
};
constexpr int kInputFaultCount = 10;
const char* inputFaultName(InputFault fault);

/// Plausibility limits for inputs ("absurd" values). Defaults suit road vehicles and the paper's rig.
struct InputLimits {
  double max_load_n = 1.0e5;                    ///< largest plausible wheel load [N], > 0
  double max_abs_slip_angle_rad = 1.0;          ///< largest plausible |slip angle| [rad], in (0, pi/2)
  double max_abs_slip_ratio = 1.0;              ///< largest plausible |slip ratio| [-], in (0, 1]
  double max_abs_path_curvature_per_m = 100.0;  ///< largest plausible |path curvature| [1/m] (rig: 16.7)
  double max_speed_mps = 100.0;                 ///< largest plausible speed [m/s], > 0
  double min_temperature_c = -60.0;             ///< lowest plausible tread temperature [degC]
  double max_temperature_c = 250.0;             ///< highest plausible tread temperature [degC]

  bool validate(std::string* error) const;

  InputFault checkLoad(double load_n) const;
  InputFault checkSlip(double slip_angle_rad, double slip_ratio, double path_curvature_per_m) const;
  InputFault checkSpeed(double speed_mps) const;
  InputFault checkTemperature(double temperature_c) const;
};

/// Input stamps this close count as equal [s]: stamps have 1 ns resolution, step times carry floating-point rounding.
constexpr double kInputStampTolerance_s = 1e-6;

/// One input sample of one wheel, as a bag or a subscriber delivers it.
struct InputSample {
  double t_s = 0.0;  ///< arrival time [s] (the node's clock, or under simulated time the message's stamp)
  InputKind kind = InputKind::kLoad;
  /// load_n | (slip_angle_rad, slip_ratio, path_curvature_per_m) | speed_mps | temperature_c
  double value[3] = {0.0, 0.0, 0.0};
};

/// Latest accepted input samples of one wheel, with counters. Plain data: copyable without allocation.
class WheelInputs {
 public:
  explicit WheelInputs(const InputLimits& limits = InputLimits()) : limits_(limits) {}

  /// Each setter validates the sample; t_s is its arrival time [s] (the clock step() uses).
  /// A rejected sample is counted and invalidates that input; the fault is returned.
  InputFault setLoad(double t_s, double load_n);
  InputFault setSlip(double t_s, double slip_angle_rad, double slip_ratio, double path_curvature_per_m);
  InputFault setSpeed(double t_s, double speed_mps);
  InputFault setTemperature(double t_s, double temperature_c);
  /// The setter of the sample's kind.
  InputFault apply(const InputSample& sample);

  struct Sample {
    bool valid = false;             ///< a sample was accepted and no invalid one came after it
    double stamp_s = 0.0;           ///< arrival time of the accepted sample [s]
    double received_s = 0.0;        ///< arrival time of the latest sample, accepted or rejected [s]
    std::uint64_t received = 0;     ///< samples received, valid or not [-]
    std::uint64_t rejected = 0;     ///< samples rejected [-]
    InputFault last_fault = InputFault::kNone;  ///< fault of the most recent rejected sample
  };
  const Sample& sample(InputKind kind) const { return samples_[static_cast<int>(kind)]; }
  /// Rejected samples of all inputs by fault class [-].
  std::uint64_t faultCount(InputFault fault) const { return fault_counts_[static_cast<int>(fault)]; }
  std::uint64_t totalRejected() const;

  double load_n() const { return load_n_; }                    ///< latest valid Fz [N]
  double slipAngle_rad() const { return slip_angle_rad_; }     ///< latest valid alpha [rad]
  double slipRatio() const { return slip_ratio_; }             ///< latest valid kappa [-]
  double pathCurvature_per_m() const { return curvature_; }   ///< latest valid 1/R [1/m]
  double speed_mps() const { return speed_mps_; }              ///< latest valid V [m/s]
  double temperature_c() const { return temperature_c_; }      ///< latest valid T [degC]
  const InputLimits& limits() const { return limits_; }

 private:
  InputFault record(InputKind kind, double t_s, InputFault fault);

  InputLimits limits_;
  std::array<Sample, kInputKindCount> samples_{};
  std::array<std::uint64_t, kInputFaultCount> fault_counts_{};
  double load_n_ = 0.0, slip_angle_rad_ = 0.0, slip_ratio_ = 0.0, curvature_ = 0.0, speed_mps_ = 0.0;
  double temperature_c_ = 0.0;
};

struct WheelEstimatorParams {
  InputLimits limits;
  double stale_timeout_s = 0.5;  ///< an input older than this at step time is stale [s], > 0
  double max_step_s = 1.0;       ///< a forward time step longer than this is a time jump [s], > stale_timeout_s

  bool validate(std::string* error) const;
};

/// Why a step did or did not integrate.
enum class WheelStatus : std::uint8_t {
  kOk = 0,            ///< evaluated from fresh, valid inputs
  kLowSpeed = 1,      ///< evaluated under the low-speed convention (WearModel)
  kNoInput = 2,       ///< a required input (load, slip, speed) never arrived
  kStaleInput = 3,    ///< a required input is older than stale_timeout_s
  kInvalidInput = 4,  ///< the latest sample of a required input was rejected
  kTimeJump = 5       ///< the clock jumped; integration restarts at this step
};
constexpr int kWheelStatusCount = 6;
const char* wheelStatusName(WheelStatus status);

/// What one step produced. Fields of the wear result are those of the last evaluation (zero before any).
struct WheelOutput {
  WheelStatus status = WheelStatus::kNoInput;
  bool evaluated = false;            ///< the model was evaluated at this step
  bool integrated = false;           ///< the interval ending at this step was added to the accumulators
  Preset preset = Preset::kStandard;  ///< preset of the last evaluation
  WearResult result;                 ///< last model result (forces, wear rates, fractions)
  double accumulated_loss_kg = 0.0;  ///< accumulated tread mass loss [kg]
  double distance_m = 0.0;           ///< accumulated distance travelled while integrating [m]
  double tread_depth_loss_m = 0.0;   ///< equivalent uniform tread depth lost [m]
  double remaining_tread_depth_m = 0.0;  ///< new tread depth minus the loss, >= 0 [m]
};

/// Persistent part of a wheel's state (what the state store saves).
struct WheelAccumulators {
  double accumulated_loss_kg = 0.0;  ///< [kg], >= 0
  double distance_m = 0.0;           ///< [m], >= 0
};

class WheelEstimator {
 public:
  /// @throw std::invalid_argument naming the field for invalid params or material.
  WheelEstimator(const WheelEstimatorParams& params, const MaterialParams& material);

  /// Samples inputs at time now_s [s], evaluates the model and integrates. Allocates nothing.
  /// @param fields optional local fields, pre-sized for the model's active preset
  const WheelOutput& step(double now_s, const WheelInputs& inputs, const WearModel& model,
                          PatchFields* fields = nullptr);

  /// Sets the accumulators (restore from the state store); the next step starts a new integration interval.
  void restore(const WheelAccumulators& accumulators);
  /// Tire change: zero accumulators; the next step starts a new interval.
  void reset() { restore(WheelAccumulators()); }
  WheelAccumulators accumulators() const { return {output_.accumulated_loss_kg, output_.distance_m}; }

  const WheelOutput& output() const { return output_; }
  const WheelEstimatorParams& params() const { return params_; }
  std::uint64_t backwardJumps() const { return backward_jumps_; }  ///< steps with dt < 0 [-]
  std::uint64_t forwardJumps() const { return forward_jumps_; }    ///< steps with dt > max_step_s [-]
  std::uint64_t staleSteps() const { return stale_steps_; }        ///< steps with a stale input [-]
  std::uint64_t evaluations() const { return evaluations_; }       ///< model evaluations [-]
  double unaccountedTime_s() const { return unaccounted_s_; }      ///< elapsed time not integrated [s]
  /// Elapsed time not integrated because of `cause` [s]: kNoInput, kStaleInput, kInvalidInput or kTimeJump (an
  /// interval that ends at a usable step after an unusable one is lost to the cause of the unusable one; after a
  /// restore() or reset(), to kNoInput). Zero for kOk and kLowSpeed; the four sum to unaccountedTime_s().
  double unaccountedTime_s(WheelStatus cause) const { return unaccounted_by_cause_s_[static_cast<int>(cause)]; }
  double integratedTime_s() const { return integrated_s_; }        ///< elapsed time integrated [s]

 private:
  void updateDepth();
  void loseInterval(double dt, WheelStatus cause);

  WheelEstimatorParams params_;
  MaterialParams material_;
  double mass_per_depth_kg_per_m_;
  WheelOutput output_;
  bool have_time_ = false;
  double last_time_s_ = 0.0;
  bool prev_evaluated_ = false;  ///< the previous step evaluated from valid inputs (interval start usable)
  WheelStatus prev_cause_ = WheelStatus::kNoInput;  ///< why the previous step was unusable (when it was)
  double prev_wear_kg_per_s_ = 0.0, prev_speed_mps_ = 0.0;
  std::uint64_t backward_jumps_ = 0, forward_jumps_ = 0, stale_steps_ = 0, evaluations_ = 0;
  double unaccounted_s_ = 0.0, integrated_s_ = 0.0;
  std::array<double, kWheelStatusCount> unaccounted_by_cause_s_{};
};

/// Whether the required inputs (load, slip, speed) are usable at now_s [s]: kOk, or the most actionable problem
/// (an invalid input over a stale one over a missing one). The rule WheelEstimator::step() applies.
WheelStatus requiredInputStatus(const WheelInputs& inputs, double now_s, double stale_timeout_s);

/// The operating point of a wheel's inputs at time now_s [s]: load, speed and slips as they are; the tread
/// temperature when valid and no older than stale_timeout_s [s], else NaN (unknown). WheelEstimator::step(),
/// the node's planner service and its markers all evaluate this point.
OperatingPoint operatingPoint(const WheelInputs& inputs, double now_s, double stale_timeout_s);

/// Evaluates a wheel's inputs as the live estimator does: a zero load (wheel off the ground) carries no force and
/// wears nothing (*result = WearResult(), *fields emptied, kOk); otherwise the model at operatingPoint() (fields, if
/// given, sized for the preset as WearModel::evaluate() requires). Allocates nothing.
EvalStatus evaluateInputs(const WearModel& model, const WheelInputs& inputs, double now_s, double stale_timeout_s,
                          WearResult* result, PatchFields* fields = nullptr);

}  // namespace tread_wear
