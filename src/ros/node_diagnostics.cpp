#include "tread_wear/ros/node_diagnostics.h"

#include <ros/console.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "tread_wear/pipeline/loop_clock.h"

namespace tread_wear {
namespace {

/// The causes a step can leave time unintegrated for (WheelEstimator::unaccountedTime_s(cause)).
constexpr WheelStatus kLossCauses[] = {WheelStatus::kNoInput, WheelStatus::kStaleInput, WheelStatus::kInvalidInput,
                                       WheelStatus::kTimeJump};

template <typename... Args>
std::string printed(const char* format, Args... args) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, format, args...);
  return buffer;
}

}  // namespace

double NodeDiagnostics::IntervalTime::faultShare() const {
  const double elapsed_s = integrated_s + unintegrated_s;
  return elapsed_s > 0.0 ? fault_s / elapsed_s : 0.0;
}

std::string NodeDiagnostics::IntervalTime::describe() const {
  std::string causes;
  for (WheelStatus cause : kLossCauses) {
    const double lost_s = by_cause_s[static_cast<int>(cause)];
    if (lost_s > 0.0)
      causes += std::string(causes.empty() ? "" : ", ") + wheelStatusName(cause) + printed(" %.3f s", lost_s);
  }
  return printed("%.3f s of %.3f s not integrated", unintegrated_s, integrated_s + unintegrated_s) + " (" + causes +
         ")";
}

NodeDiagnostics::IntervalTime NodeDiagnostics::takeInterval(const WheelSnapshot& s, TimeCounters* previous) {
  IntervalTime interval;
  interval.integrated_s = s.integrated_time_s - previous->integrated_s;
  for (WheelStatus cause : kLossCauses) {
    const int c = static_cast<int>(cause);
    const double lost_s = s.unaccounted_by_cause_s[c] - previous->unintegrated_by_cause_s[c];
    interval.by_cause_s[c] = lost_s;
    interval.unintegrated_s += lost_s;
    if (cause != WheelStatus::kNoInput) interval.fault_s += lost_s;
  }
  previous->integrated_s = s.integrated_time_s;
  previous->unintegrated_by_cause_s = s.unaccounted_by_cause_s;
  return interval;
}

NodeDiagnostics::NodeDiagnostics(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const LoopStatus& loop,
                                 const NodePersistence& persistence, const NodeReconfigure& reconfigure)
    : wheels_(wheels),
      loop_(loop),
      persistence_(persistence),
      reconfigure_(reconfigure),
      history_(wheels.size()),
      vehicle_history_(wheels.size()) {}

void NodeDiagnostics::addTo(diagnostic_updater::Updater* updater) {
  updater->setHardwareID("tread_wear");
  updater->add("update loop", this, &NodeDiagnostics::diagnoseLoop);
  updater->add("persistence", this, &NodeDiagnostics::diagnosePersistence);
  for (std::size_t i = 0; i < wheels_.size(); ++i)
    updater->add("wheel " + wheels_[i]->config().name, [this, i](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      diagnoseWheel(i, ros::Time::now().toSec(), steadyNow_s(), stat);
    });
  updater->add("vehicle", this, &NodeDiagnostics::diagnoseVehicle);
}

void NodeDiagnostics::diagnoseWheel(std::size_t index, double now_s, double wall_s,
                                    diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const WheelPipeline& w = *wheels_[index];
  WheelHistory& h = history_[index];
  const WheelSnapshot s = w.snapshot();
  const WheelOutput& out = s.output;
  const double dt = h.wall_s > 0.0 ? wall_s - h.wall_s : 0.0;
  stat.add("tire_id", s.tire_id);
  stat.add("status", wheelStatusName(out.status));
  for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed, InputKind::kTemperature}) {
    const WheelInputs::Sample& sample = s.inputs.sample(kind);
    const int k = static_cast<int>(kind);
    const std::string name = inputKindName(kind);
    const double rate = dt > 0.0 ? static_cast<double>(sample.received - h.received[k]) / dt : 0.0;
    h.received[k] = sample.received;
    stat.addf(name + " rate [Hz]", "%.1f", rate);
    if (sample.received > 0 && sample.valid)
      stat.addf(name + " age [s]", "%.3f", now_s - sample.stamp_s);
    else
      stat.add(name + " age [s]", sample.received == 0 ? "never received" : "invalid");
    stat.add(name + " rejected", sample.rejected);
  }
  for (int f = 1; f < kInputFaultCount; ++f) {
    const InputFault fault = static_cast<InputFault>(f);
    if (s.inputs.faultCount(fault) > 0)
      stat.add(std::string("invalid: ") + inputFaultName(fault), s.inputs.faultCount(fault));
  }
  stat.add("stale steps", s.stale_steps);
  stat.add("time jumps backward", s.backward_jumps);
  stat.add("time jumps forward", s.forward_jumps);
  if (w.inputTime()) stat.add("steps past a lagging input", s.steps_past_lagging_input);
  stat.addf("unaccounted time [s]", "%.3f", s.unaccounted_time_s);
  const IntervalTime interval = takeInterval(s, &h.time);
  stat.addf("integrated since last report [s]", "%.3f", interval.integrated_s);
  stat.addf("unintegrated since last report [s]", "%.3f", interval.unintegrated_s);
  for (WheelStatus cause : kLossCauses)
    stat.addf(std::string("unintegrated since last report: ") + wheelStatusName(cause) + " [s]", "%.3f",
              interval.by_cause_s[static_cast<int>(cause)]);
  stat.add("evaluations", s.evaluations);
  stat.addf("last evaluation [us]", "%.1f", w.lastEvaluation_us());
  stat.addf("max evaluation [us]", "%.1f", w.maxEvaluation_us());
  stat.add("deadline overruns", w.deadlineOverruns());
  const Preset active = w.activePreset();
  const Preset configured = loop_.configuredPreset();
  stat.add("preset", presetName(active));
  stat.add("degraded", active < configured ? "true" : "false");
  stat.add("degraded evaluations", w.degradedEvaluations());
  stat.addf("accumulated loss [kg]", "%.9g", out.accumulated_loss_kg);
  stat.addf("distance [m]", "%.6g", out.distance_m);
  stat.addf("remaining tread depth [m]", "%.6g", out.remaining_tread_depth_m);

  const std::uint64_t rejected = s.inputs.totalRejected();
  const bool new_rejects = rejected > h.rejected;
  if (s.backward_jumps > h.backward || s.forward_jumps > h.forward)
    ROS_WARN_THROTTLE(5.0, "wheel %s: clock jumped (%llu backward, %llu forward so far); accumulated state kept, "
                      "integration restarted", w.config().name.c_str(),
                      static_cast<unsigned long long>(s.backward_jumps),
                      static_cast<unsigned long long>(s.forward_jumps));
  h.rejected = rejected;
  h.backward = s.backward_jumps;
  h.forward = s.forward_jumps;
  h.wall_s = wall_s;

  if (interval.unintegrated_s > 0.0) {
    // Whatever the status at this instant: time lost between two reports is never reported as OK.
    const bool error = interval.faultShare() > kErrorUnintegratedShare;
    const std::string what = interval.describe() + " since the last report";
    stat.summary(error ? diagnostic_msgs::DiagnosticStatus::ERROR : diagnostic_msgs::DiagnosticStatus::WARN, what);
    if (interval.fault_s > 0.0)
      ROS_WARN_THROTTLE(5.0, "wheel %s: %s; accumulated loss incomplete", w.config().name.c_str(), what.c_str());
    return;
  }
  switch (out.status) {
    case WheelStatus::kOk:
    case WheelStatus::kLowSpeed:
      if (new_rejects)
        stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid inputs rejected");
      else if (active < configured)
        stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "preset degraded by the time budget");
      else
        stat.summary(diagnostic_msgs::DiagnosticStatus::OK, out.status == WheelStatus::kOk ? "ok" : "low speed");
      break;
    case WheelStatus::kNoInput: stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for inputs"); break;
    case WheelStatus::kStaleInput:
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "stale input: not evaluated");
      break;
    case WheelStatus::kInvalidInput:
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid input: not evaluated");
      break;
    case WheelStatus::kTimeJump: stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "time jump"); break;
  }
}

void NodeDiagnostics::diagnoseVehicle(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  double loss_kg = 0.0, worst_since_start_s = 0.0, worst_share = 0.0;
  std::string incomplete;  // the wheels that lost time since the last report, with what they lost
  for (std::size_t i = 0; i < wheels_.size(); ++i) {
    const WheelSnapshot s = wheels_[i]->snapshot();
    loss_kg += s.output.accumulated_loss_kg;
    worst_since_start_s = std::max(worst_since_start_s, s.unaccounted_time_s);
    const IntervalTime interval = takeInterval(s, &vehicle_history_[i]);
    if (interval.unintegrated_s > 0.0)
      incomplete += (incomplete.empty() ? "" : "; ") + wheels_[i]->config().name + " " + interval.describe();
    worst_share = std::max(worst_share, interval.faultShare());
  }
  stat.addf("accumulated loss [kg]", "%.9g", loss_kg);
  stat.add("complete since last report", incomplete.empty() ? "true" : "false");
  stat.addf("unaccounted time, worst wheel [s]", "%.3f", worst_since_start_s);
  if (incomplete.empty()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "loss complete");
    return;
  }
  const std::string what = "loss incomplete since the last report: " + incomplete;
  stat.summary(worst_share > kErrorUnintegratedShare ? diagnostic_msgs::DiagnosticStatus::ERROR
                                                      : diagnostic_msgs::DiagnosticStatus::WARN,
               what);
}

void NodeDiagnostics::diagnoseLoop(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const std::uint64_t overruns = loop_.cycle_overruns.load();
  const std::string rejection = reconfigure_.lastRejection();
  stat.add("cycles", loop_.cycles.load());
  stat.addf("update rate [Hz]", "%.3f", 1.0 / loop_.period_s.load());
  stat.addf("budget [us]", "%.1f", loop_.budget_us.load());
  stat.addf("last cycle [us]", "%.1f", loop_.last_cycle_us.load());
  stat.addf("max cycle [us]", "%.1f", loop_.max_cycle_us.load());
  stat.add("cycle overruns", overruns);
  stat.add("skipped publications", loop_.skipped_publications.load());
  stat.add("rejected reconfigure", rejection.empty() ? "none" : rejection);
  if (overruns > last_cycle_overruns_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "update cycle exceeded its period");
    ROS_WARN_THROTTLE(10.0, "update loop: %llu cycle(s) longer than the period so far (max %.0f us)",
                      static_cast<unsigned long long>(overruns), loop_.max_cycle_us.load());
  } else if (!rejection.empty()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "reconfigure rejected: " + rejection);
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
  }
  last_cycle_overruns_ = overruns;
}

void NodeDiagnostics::diagnosePersistence(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const NodePersistence::Status s = persistence_.status();
  stat.add("state_file", s.state_file.empty() ? "(persistence off)" : s.state_file);
  stat.add("restore", s.restore);
  stat.addf("seconds since last save", "%.1f", s.seconds_since_save);
  if (!s.problem.empty())
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, s.problem);
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, s.saving ? "ok" : "persistence off");
}

}  // namespace tread_wear
