#include "tread_wear/pipeline/wheel_pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/io/params_io.h"
#include "tread_wear/pipeline/loop_clock.h"

namespace tread_wear {

WheelPipeline::WheelPipeline(const WheelConfig& config, const TireParams& tire, const NodeConfig& node)
    : config_(config),
      tire_(tire),
      model_options_(node.model),
      estimator_params_(node.estimator),
      inputs_(node.estimator.limits),
      model_(std::make_unique<WearModel>(tire, node.model)),
      estimator_(node.estimator, tire.material),
      step_inputs_(node.estimator.limits),
      tire_id_(config.tire_id),
      loop_inputs_(node.estimator.limits),
      planner_model_(std::make_unique<WearModel>(tire, node.model)),
      active_preset_(static_cast<int>(node.model.preset)) {
  loop_tire_id_.reserve(kMaxTireIdLength);
  loop_tire_id_ = tire_id_;
}

std::unique_ptr<WheelPipeline> WheelPipeline::load(const WheelConfig& config, const NodeConfig& node) {
  TireParams tire;
  try {
    tire = loadTireParams(config.tire_params);
  } catch (const std::exception& e) {
    throw std::runtime_error("wheel " + config.name + ": cannot load tire parameters '" + config.tire_params +
                             "': " + e.what());
  }
  return std::make_unique<WheelPipeline>(config, tire, node);
}

InputFault WheelPipeline::setLoad(double t_s, double load_n) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  return inputs_.setLoad(t_s, load_n);
}

InputFault WheelPipeline::setSlip(double t_s, double slip_angle_rad, double slip_ratio, double path_curvature_per_m) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  return inputs_.setSlip(t_s, slip_angle_rad, slip_ratio, path_curvature_per_m);
}

InputFault WheelPipeline::setSpeed(double t_s, double speed_mps) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  return inputs_.setSpeed(t_s, speed_mps);
}

InputFault WheelPipeline::setTemperature(double t_s, double temperature_c) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  return inputs_.setTemperature(t_s, temperature_c);
}

void WheelPipeline::setInputTime(bool on) {
  std::lock_guard<std::mutex> lock(step_mutex_);
  if (!on) {
    timeline_.reset();
    return;
  }
  InputTimelineParams params;
  params.max_lead_s = estimator_params_.max_step_s;
  timeline_ = std::make_unique<InputTimeline>(params);
}

InputFault WheelPipeline::receive(const InputSample& sample, double wall_s, const StepSettings& settings) {
  InputFault fault;
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    fault = inputs_.apply(sample);
  }
  std::lock_guard<std::mutex> step_lock(step_mutex_);
  if (!timeline_) return fault;
  InputTimeline::Push pushed = timeline_->push(sample, wall_s);
  if (pushed == InputTimeline::Push::kBackward) {
    // A looping bag: finish the old time line, then start a new one (the estimator counts the backward jump).
    while (stepTimeline(wall_s, settings, true)) {
    }
    timeline_->restart();
    pushed = timeline_->push(sample, wall_s);
  }
  // A full ring: release steps without the lagging input until there is room (each releases samples, so this ends).
  while (pushed == InputTimeline::Push::kFull && stepTimeline(wall_s, settings, true))
    pushed = timeline_->push(sample, wall_s);
  while (stepTimeline(wall_s, settings, false)) {
  }
  return fault;
}

bool WheelPipeline::stepTimeline(double wall_s, const StepSettings& settings, bool flush) {
  double t_s = 0.0;
  if (!timeline_->nextStep(wall_s, settings.period_s, flush, &loop_inputs_, &t_s)) return false;
  stepLocked(t_s, settings);
  return true;
}

const WheelOutput& WheelPipeline::step(double now_s, const StepSettings& settings) {
  std::lock_guard<std::mutex> step_lock(step_mutex_);
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    loop_inputs_ = inputs_;
  }
  stepLocked(now_s, settings);
  return loop_output_;
}

void WheelPipeline::stepLocked(double now_s, const StepSettings& settings) {
  // Live reconfiguration: plain stores in the model. Under a budget the model picks the finest preset whose
  // measured time fits (wear_model.h).
  if (model_->wantedPreset() != settings.preset) model_->setPreset(settings.preset);
  if (model_->timeBudget() != settings.budget_s) model_->setTimeBudget(settings.budget_s);
  loop_stepped_ = true;
  loop_step_time_s_ = now_s;
  double eval_us;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    const double t0 = steadyNow_s();
    loop_output_ = estimator_.step(now_s, loop_inputs_, *model_);
    eval_us = 1e6 * (steadyNow_s() - t0);
    step_inputs_ = loop_inputs_;
    step_time_s_ = now_s;
    loop_tire_id_ = tire_id_;
    loop_unaccounted_s_ = estimator_.unaccountedTime_s();
    if (timeline_) steps_past_lagging_ = timeline_->stepsPastLaggingInput();
  }
  if (loop_output_.evaluated) {
    last_eval_us_.store(eval_us, std::memory_order_relaxed);
    atomicMax(max_eval_us_, eval_us);
    if (eval_us > settings.deadline_us) overruns_.fetch_add(1, std::memory_order_relaxed);
    active_preset_.store(static_cast<int>(model_->activePreset()), std::memory_order_relaxed);
    degraded_count_.store(model_->degradedCount(), std::memory_order_relaxed);
  }
}

WheelOutput WheelPipeline::lastOutput() const {
  std::lock_guard<std::mutex> lock(step_mutex_);
  return loop_output_;
}

EvalStatus WheelPipeline::plan(const WheelInputs& inputs, Preset preset, WearResult* result) {
  std::lock_guard<std::mutex> lock(planner_mutex_);
  planner_model_->setPreset(preset);
  // The planner's states are hypothetical and timeless: every sample, the temperature included, is current.
  return evaluateInputs(*planner_model_, inputs, 0.0, estimator_params_.stale_timeout_s, result);
}

WheelAccumulators WheelPipeline::changeTire(const std::string& tire_id, double unix_s, std::string* old_tire_id) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  const WheelAccumulators old = estimator_.accumulators();
  *old_tire_id = tire_id_;
  estimator_.reset();
  tire_id_ = tire_id;
  reset_unix_s_ = unix_s;
  return old;
}

WheelRecord WheelPipeline::record() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  const WheelAccumulators a = estimator_.accumulators();
  return {config_.name, tire_id_, a.accumulated_loss_kg, a.distance_m, reset_unix_s_};
}

void WheelPipeline::restore(const WheelRecord& record) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  estimator_.restore({record.accumulated_loss_kg, record.distance_m});
  // A longer id (edited by hand) is cut to what the loop's preallocated strings hold.
  tire_id_ = record.tire_id.substr(0, kMaxTireIdLength);
  reset_unix_s_ = record.reset_unix_s;
}

WheelSnapshot WheelPipeline::snapshot() const {
  WheelSnapshot s;
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    s.inputs = inputs_;
  }
  std::lock_guard<std::mutex> lock(state_mutex_);
  s.step_inputs = step_inputs_;
  s.step_time_s = step_time_s_;
  s.output = estimator_.output();
  s.tire_id = tire_id_;
  s.backward_jumps = estimator_.backwardJumps();
  s.forward_jumps = estimator_.forwardJumps();
  s.stale_steps = estimator_.staleSteps();
  s.evaluations = estimator_.evaluations();
  s.unaccounted_time_s = estimator_.unaccountedTime_s();
  for (int c = 0; c < kWheelStatusCount; ++c)
    s.unaccounted_by_cause_s[c] = estimator_.unaccountedTime_s(static_cast<WheelStatus>(c));
  s.integrated_time_s = estimator_.integratedTime_s();
  s.steps_past_lagging_input = steps_past_lagging_;
  return s;
}

WheelPipeline* findWheel(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const std::string& name) {
  for (const auto& w : wheels)
    if (w->config().name == name) return w.get();
  return nullptr;
}

}  // namespace tread_wear
