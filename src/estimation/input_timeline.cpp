#include "tread_wear/estimation/input_timeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

bool InputTimelineParams::validate(std::string* error) const {
  if (!(max_lead_s > 0.0) || !std::isfinite(max_lead_s))
    return failValidation(error, "max_lead_s", max_lead_s, "finite and > 0");
  if (!(wait_s >= 0.0) || !std::isfinite(wait_s)) return failValidation(error, "wait_s", wait_s, "finite and >= 0");
  if (capacity < 2) return failValidation(error, "capacity", capacity, ">= 2");
  return true;
}

InputTimeline::InputTimeline(const InputTimelineParams& params) : params_(params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid input timeline parameters: " + error);
  for (Ring& r : rings_) r.samples.resize(params.capacity);
}

bool InputTimeline::gating(InputKind kind) const {
  return kind != InputKind::kTemperature || rings_[static_cast<int>(kind)].arrived;
}

InputTimeline::Push InputTimeline::push(const InputSample& sample, double wall_s) {
  Ring& r = rings_[static_cast<int>(sample.kind)];
  if (r.arrived && sample.t_s < r.last_stamp_s - kInputStampTolerance_s) return Push::kBackward;
  if (r.size == r.samples.size()) {
    ++full_rings_;
    return Push::kFull;
  }
  bool any = false;
  for (const Ring& other : rings_) any = any || other.arrived;
  r.samples[(r.head + r.size) % r.samples.size()] = sample;
  ++r.size;
  r.arrived = true;
  r.last_stamp_s = sample.t_s;
  newest_s_ = any ? std::max(newest_s_, sample.t_s) : sample.t_s;
  // Lagging is observed here, at arrivals: a node that was not running (descheduled, stalled) saw nothing lag.
  for (int k = 0; k < kInputKindCount; ++k) {
    Ring& other = rings_[k];
    const bool lagging = gating(static_cast<InputKind>(k)) &&
                         (!other.arrived || other.last_stamp_s < newest_s_ - params_.max_lead_s);
    if (!lagging) other.lagging = false;
    else if (!other.lagging) {
      other.lagging = true;
      other.lagging_since_wall_s = wall_s;
    }
  }
  return Push::kTaken;
}

double InputTimeline::horizon_s(double wall_s, bool flush, bool* forced) const {
  double natural_s = std::numeric_limits<double>::infinity();
  double waited_s = natural_s;
  const double lead_limit_s = newest_s_ - params_.max_lead_s;
  for (int k = 0; k < kInputKindCount; ++k) {
    if (!gating(static_cast<InputKind>(k))) continue;
    const Ring& r = rings_[k];
    const double latest_s = r.arrived ? r.last_stamp_s : -std::numeric_limits<double>::infinity();
    natural_s = std::min(natural_s, latest_s);
    const bool given_up = r.lagging && wall_s - r.lagging_since_wall_s > params_.wait_s;
    waited_s = std::min(waited_s, given_up ? lead_limit_s : latest_s);
  }
  const double horizon = flush ? newest_s_ : waited_s;
  *forced = horizon > natural_s + kInputStampTolerance_s;
  return horizon;
}

bool InputTimeline::nextStep(double wall_s, double step_s, bool flush, WheelInputs* inputs, double* t_s) {
  if (!started_) {
    // The grid starts at the earliest buffered stamp, once the first step may be released (all gating inputs here,
    // or no longer waited for), as DriveReplay's starts at the drive's first sample.
    double first_s = std::numeric_limits<double>::infinity();
    for (const Ring& r : rings_)
      if (r.size > 0) first_s = std::min(first_s, r.samples[r.head].t_s);
    if (!std::isfinite(first_s)) return false;
    bool forced = false;
    if (first_s > horizon_s(wall_s, flush, &forced) + kInputStampTolerance_s) return false;
    started_ = true;
    t0_s_ = first_s;
    step_s_ = step_s;
    next_k_ = 0;
  } else if (step_s != step_s_) {
    // A new update rate: the grid continues from the last step at the new spacing.
    t0_s_ += static_cast<double>(next_k_ - 1) * step_s_;
    step_s_ = step_s;
    next_k_ = 1;
  }
  const double t = t0_s_ + static_cast<double>(next_k_) * step_s_;
  bool forced = false;
  if (t > horizon_s(wall_s, flush, &forced) + kInputStampTolerance_s) return false;
  for (Ring& r : rings_) {
    while (r.size > 0 && r.samples[r.head].t_s <= t + kInputStampTolerance_s) {
      inputs->apply(r.samples[r.head]);
      r.head = (r.head + 1) % r.samples.size();
      --r.size;
    }
  }
  if (forced) ++steps_past_lagging_;
  ++next_k_;
  *t_s = t;
  return true;
}

void InputTimeline::restart() {
  for (Ring& r : rings_) {
    r.head = r.size = 0;
    r.arrived = r.lagging = false;
  }
  started_ = false;
}

}  // namespace tread_wear
