#include "tread_wear/ros/node_reconfigure.h"

#include <ros/console.h>

namespace tread_wear {
namespace {

void writeLoopSettings(const NodeConfig& c, LoopStatus* loop) {
  loop->period_s = 1.0 / c.update_rate_hz;
  loop->budget_us = c.budget_us;
  loop->preset = static_cast<int>(c.model.preset);
}

}  // namespace

NodeReconfigure::NodeReconfigure(const NodeConfig& config, LoopStatus* loop) : config_(config), loop_(loop) {
  writeLoopSettings(config_, loop_);
}

tread_wear::TreadWearConfig NodeReconfigure::current() const {
  std::lock_guard<std::mutex> lock(mutex_);
  tread_wear::TreadWearConfig c = tread_wear::TreadWearConfig::__getDefault__();
  c.update_rate_hz = config_.update_rate_hz;
  c.budget_us = config_.budget_us;
  c.preset = presetName(config_.model.preset);
  return c;
}

bool NodeReconfigure::apply(tread_wear::TreadWearConfig* request) {
  std::unique_lock<std::mutex> lock(mutex_);
  NodeConfig candidate = config_;
  candidate.update_rate_hz = request->update_rate_hz;
  candidate.budget_us = request->budget_us;
  std::string error;
  bool valid = parsePreset(request->preset, &candidate.model.preset);
  if (!valid) error = "preset = " + request->preset + ": must be " + kPresetChoices;
  valid = valid && candidate.validate(&error);
  if (!valid) {
    rejection_ = error;
    request->update_rate_hz = config_.update_rate_hz;
    request->budget_us = config_.budget_us;
    request->preset = presetName(config_.model.preset);
    lock.unlock();
    ROS_ERROR("dynamic_reconfigure: rejected (%s); keeping update_rate_hz %.6g [Hz], budget_us %.6g [us], preset %s",
              error.c_str(), request->update_rate_hz, request->budget_us, request->preset.c_str());
    return false;
  }
  config_ = candidate;
  rejection_.clear();
  writeLoopSettings(config_, loop_);
  ROS_INFO("dynamic_reconfigure: update_rate_hz %.6g [Hz], budget_us %.6g [us], preset %s", config_.update_rate_hz,
           config_.budget_us, presetName(config_.model.preset));
  return true;
}

std::string NodeReconfigure::lastRejection() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rejection_;
}

}  // namespace tread_wear
