#include "tread_wear/vehicle/drive_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tread_wear {

SpeedTrace::SpeedTrace(double start_speed_mps, const std::vector<SpeedCell>& cells, double duration_s,
                       double smoothing_s, Route route)
    : duration_s_(duration_s), smoothing_s_(smoothing_s), route_(std::move(route)) {
  if (!(duration_s > 0.0) || !std::isfinite(duration_s))
    throw std::invalid_argument("speed trace: duration " + std::to_string(duration_s) + " s must be > 0");
  if (!(start_speed_mps >= 0.0) || !std::isfinite(start_speed_mps))
    throw std::invalid_argument("speed trace: start speed " + std::to_string(start_speed_mps) + " m/s must be >= 0");
  if (!(smoothing_s >= 0.0) || !std::isfinite(smoothing_s))
    throw std::invalid_argument("speed trace: smoothing window " + std::to_string(smoothing_s) + " s must be >= 0");
  t_ = {0.0};
  v_ = {start_speed_mps};
  s_ = {0.0};
  p_ = {0.0};
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const double h = cells[k].duration_s, a = cells[k].accel_mps2;
    if (!(h > 0.0) || !std::isfinite(h) || !std::isfinite(a))
      throw std::invalid_argument("speed trace: cell " + std::to_string(k) + " needs a finite duration > 0");
    const double v0 = v_.back(), s0 = s_.back();
    // A cell braking to rest ends within a rounding error of zero, either side; it ends at rest, so that a dwell
    // after it stands still. Further below zero is a wrong trace.
    const double rounding = 1e-9 * std::max(1.0, v0);
    const double v1 = std::fabs(v0 + a * h) < rounding ? 0.0 : v0 + a * h;
    if (v1 < 0.0)
      throw std::invalid_argument("speed trace: cell " + std::to_string(k) + " ends at " + std::to_string(v1) +
                                  " m/s");
    a_.push_back(a);
    p_.push_back(p_.back() + h * (s0 + h * (v0 / 2.0 + a * h / 6.0)));
    s_.push_back(s0 + h * (v0 + a * h / 2.0));
    v_.push_back(v1);
    t_.push_back(t_.back() + h);
  }
  distance_m_ = position(duration_s_);
}

SpeedTrace::Raw SpeedTrace::raw(double t_s) const {
  if (t_s <= 0.0) return {v_.front(), v_.front() * t_s, v_.front() * t_s * t_s / 2.0};
  if (t_s >= t_.back() || a_.empty()) {
    const double dt = t_s - t_.back();
    return {v_.back(), s_.back() + v_.back() * dt, p_.back() + dt * (s_.back() + v_.back() * dt / 2.0)};
  }
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t_s) - t_.begin()) - 1;
  const double dt = t_s - t_[k], a = a_[k];
  return {std::max(0.0, v_[k] + a * dt), s_[k] + dt * (v_[k] + a * dt / 2.0),
          p_[k] + dt * (s_[k] + dt * (v_[k] / 2.0 + a * dt / 6.0))};
}

double SpeedTrace::position(double t_s) const {
  if (smoothing_s_ == 0.0) return raw(t_s).s;
  return (raw(t_s + smoothing_s_ / 2.0).p - raw(t_s - smoothing_s_ / 2.0).p) / smoothing_s_;
}

VehicleMotion SpeedTrace::at(double t_s) const {
  if (smoothing_s_ == 0.0) {
    const Raw r = raw(t_s);
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t_s) - t_.begin());
    const double a = t_s < 0.0 || k == 0 || k > a_.size() ? 0.0 : a_[k - 1];
    return {r.v, a, route_.curvature(r.s)};
  }
  const double half = smoothing_s_ / 2.0;
  const Raw before = raw(t_s - half), after = raw(t_s + half);
  return {std::max(0.0, (after.s - before.s) / smoothing_s_), (after.v - before.v) / smoothing_s_,
          route_.curvature((after.p - before.p) / smoothing_s_)};
}

}  // namespace tread_wear
