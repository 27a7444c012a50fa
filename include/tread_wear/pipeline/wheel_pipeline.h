#pragma once
/// @file wheel_pipeline.h
/// One wheel of the wear node from its inputs to its last step: the latest accepted inputs (validated on arrival by
/// WheelInputs), the live model and estimator that the update loop steps (in input time, the subscribers), the
/// planner model of the evaluate_wear service, the mounted tire's id and the evaluation timing. Free of any
/// middleware: tread_wear_node (ROS 1, ros/wheel_pipeline.h fills its message from readLastStep) composes it, and
/// so would a second front end; the tests drive it without a master (test/ros/test_node_parts.cpp).
///
/// Locks (each held for a copy or one step, never across calls):
///   step mutex     step()/receive() <-> readLastStep()/lastOutput(): uncontended live (the loop does all three); in
///                  input time (simulated time) the subscribers step (receive()) and the loop publishes;
///   input mutex    subscriber callbacks (set*, receive) <-> the copy of the inputs in step();
///   state mutex    step() <-> services, diagnostics, persistence and markers (snapshots);
///   planner mutex  concurrent evaluate_wear calls on the planner model.
/// step(), receive() and readLastStep() allocate nothing and never log or do I/O (tire ids fit preallocated
/// strings).

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "tread_wear/estimation/input_timeline.h"
#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/io/state_store.h"
#include "tread_wear/io/wheel_config.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {

/// What diagnostics, persistence and the markers read of a wheel, copied under its locks.
struct WheelSnapshot {
  WheelInputs inputs;          ///< inputs as received (with their counters)
  WheelInputs step_inputs;     ///< inputs of the last loop step
  double step_time_s = 0.0;    ///< time of the last step [s] (node clock; in input time, the inputs')
  WheelOutput output;          ///< output of the last loop step
  std::string tire_id;
  std::uint64_t backward_jumps = 0, forward_jumps = 0, stale_steps = 0, evaluations = 0;
  double unaccounted_time_s = 0.0;  ///< elapsed time not integrated [s]
  std::array<double, kWheelStatusCount> unaccounted_by_cause_s{};  ///< the same by WheelStatus cause [s]
  double integrated_time_s = 0.0;   ///< elapsed time integrated [s]
  std::uint64_t steps_past_lagging_input = 0;  ///< input time: steps released without a lagging input [-]
};

class WheelPipeline {
 public:
  /// @throw std::invalid_argument for model options or estimator parameters that WearModel/WheelEstimator reject
  WheelPipeline(const WheelConfig& config, const TireParams& tire, const NodeConfig& node);
  /// Loads config.tire_params. @throw std::runtime_error naming the wheel and the file
  static std::unique_ptr<WheelPipeline> load(const WheelConfig& config, const NodeConfig& node);

  const WheelConfig& config() const { return config_; }
  const TireParams& tire() const { return tire_; }
  const WearModelOptions& modelOptions() const { return model_options_; }
  const WheelEstimatorParams& estimatorParams() const { return estimator_params_; }

  /// Subscriber side: validates and stores a sample that arrived at t_s [s]; the fault (kNone = accepted).
  InputFault setLoad(double t_s, double load_n);
  InputFault setSlip(double t_s, double slip_angle_rad, double slip_ratio, double path_curvature_per_m);
  InputFault setSpeed(double t_s, double speed_mps);
  InputFault setTemperature(double t_s, double temperature_c);

  /// Input time (the node under simulated time): steps follow the inputs' own stamps (their header stamps,
  /// tread_wear_node.cpp), not the node clock. The subscribers hand every sample to receive(), which puts the
  /// samples back in stamp order and steps the wheel on a grid of the update period in their time, each step once all
  /// its inputs have arrived (InputTimeline): the steps and the wear then depend on the data only, not on when or in
  /// which order the node gets the samples, and equal the offline replay's (DriveReplay). Set before the inputs are
  /// subscribed; allocates the timeline's buffers.
  void setInputTime(bool on);
  bool inputTime() const { return timeline_ != nullptr; }
  /// What a step needs besides its time.
  struct StepSettings {
    Preset preset = Preset::kStandard;  ///< live model preset
    double budget_s = 0.0;              ///< live model time budget [s] (0: none)
    double deadline_us = 1e9;           ///< an evaluation longer than this counts as an overrun [us]
    double period_s = 0.01;             ///< input time between two steps [s] (the update period), > 0
  };
  /// Subscriber side in input time: receives a sample at wall time wall_s [s] (steady clock), as set*() does, and
  /// takes every step it makes due. The sample's fault (kNone = accepted).
  InputFault receive(const InputSample& sample, double wall_s, const StepSettings& settings);
  /// Step (the loop, on the node clock): one step at now_s [s] with the inputs as they are, the live model set to the
  /// settings' preset and budget first. Steps are serialized with receive()'s. The result stays valid until the
  /// next step (use lastOutput() from another thread).
  const WheelOutput& step(double now_s, const StepSettings& settings);
  /// The last step as the loop publishes it (read under the step lock; references valid during the call only).
  struct LastStep {
    const WheelOutput& output;
    const std::string& tire_id;     ///< the mounted tire's id at that step
    double unaccounted_time_s;      ///< elapsed time not integrated [s]
    bool stepped;                   ///< a step was taken
    double step_time_s;             ///< its time [s] (input time: the inputs' stamps)
    bool input_time;                ///< steps follow the inputs' stamps (setInputTime)
  };
  /// Loop side: read(const LastStep&) under the step lock. Allocates nothing itself.
  template <class Read>
  void readLastStep(Read&& read) const {
    std::lock_guard<std::mutex> lock(step_mutex_);
    read(LastStep{loop_output_, loop_tire_id_, loop_unaccounted_s_, loop_stepped_, loop_step_time_s_,
                  timeline_ != nullptr});
  }
  /// Loop side: a copy of the last step's output (input time: the subscribers step). Allocates nothing.
  WheelOutput lastOutput() const;

  /// Planner (evaluate_wear): evaluateInputs() on the planner model at `preset`.
  EvalStatus plan(const WheelInputs& inputs, Preset preset, WearResult* result);

  /// Tire change: zero accumulators, new tire id (1..kMaxTireIdLength characters, checked by the caller), reset
  /// time unix_s [s since 1970]; the old tire's id and accumulators.
  WheelAccumulators changeTire(const std::string& tire_id, double unix_s, std::string* old_tire_id);
  /// Persistence: the saved record of this wheel; restore() continues from one.
  WheelRecord record() const;
  void restore(const WheelRecord& record);
  WheelSnapshot snapshot() const;

  /// Evaluation timing of the loop (atomics: read by diagnostics at any time).
  double lastEvaluation_us() const { return last_eval_us_.load(std::memory_order_relaxed); }
  double maxEvaluation_us() const { return max_eval_us_.load(std::memory_order_relaxed); }
  std::uint64_t deadlineOverruns() const { return overruns_.load(std::memory_order_relaxed); }
  Preset activePreset() const { return static_cast<Preset>(active_preset_.load(std::memory_order_relaxed)); }
  long degradedEvaluations() const { return degraded_count_.load(std::memory_order_relaxed); }

 private:
  /// One estimator step at now_s [s] on loop_inputs_ (the caller holds step_mutex_).
  void stepLocked(double now_s, const StepSettings& settings);
  /// Input time: the timeline's next step due (InputTimeline::nextStep, `flush` as there), if any, taken with
  /// stepLocked(); false when none is due (the caller holds step_mutex_).
  bool stepTimeline(double wall_s, const StepSettings& settings, bool flush);

  WheelConfig config_;
  TireParams tire_;
  WearModelOptions model_options_;
  WheelEstimatorParams estimator_params_;

  mutable std::mutex input_mutex_;
  WheelInputs inputs_;  ///< guarded by input_mutex_

  mutable std::mutex state_mutex_;
  std::unique_ptr<WearModel> model_;  ///< live model, guarded by step_mutex_
  WheelEstimator estimator_;          ///< guarded by state_mutex_
  WheelInputs step_inputs_;           ///< guarded by state_mutex_
  double step_time_s_ = 0.0;          ///< guarded by state_mutex_
  std::uint64_t steps_past_lagging_ = 0;  ///< the timeline's count at the last step, guarded by state_mutex_
  std::string tire_id_;               ///< guarded by state_mutex_
  double reset_unix_s_ = 0.0;         ///< guarded by state_mutex_

  // The stepping side's own copies (guarded by step_mutex_: the loop, or in input time the subscribers).
  mutable std::mutex step_mutex_;
  WheelInputs loop_inputs_;
  WheelOutput loop_output_;
  std::string loop_tire_id_;  ///< capacity kMaxTireIdLength: assignments never allocate
  double loop_unaccounted_s_ = 0.0;
  bool loop_stepped_ = false;       ///< a step was taken
  double loop_step_time_s_ = 0.0;   ///< its time [s]
  std::unique_ptr<InputTimeline> timeline_;  ///< input time only (setInputTime)

  std::mutex planner_mutex_;
  std::unique_ptr<WearModel> planner_model_;  ///< guarded by planner_mutex_

  std::atomic<double> last_eval_us_{0.0}, max_eval_us_{0.0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<int> active_preset_;
  std::atomic<long> degraded_count_{0};
};

/// The wheel of that name among `wheels`, or nullptr.
WheelPipeline* findWheel(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const std::string& name);

}  // namespace tread_wear
