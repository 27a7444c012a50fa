#include "tread_wear/vehicle/speed_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tread_wear {

SpeedProfile::SpeedProfile(std::vector<double> time_s, std::vector<double> speed_mps,
                           std::vector<ProfilePhase> phases, std::string name)
    : t_(std::move(time_s)), v_(std::move(speed_mps)), phases_(std::move(phases)), name_(std::move(name)) {
  if (t_.size() != v_.size())
    throw std::invalid_argument("speed profile: " + std::to_string(t_.size()) + " times but " +
                                std::to_string(v_.size()) + " speeds");
  if (t_.size() < 2) throw std::invalid_argument("speed profile: needs at least 2 samples");
  for (std::size_t i = 0; i < t_.size(); ++i) {
    if (!std::isfinite(t_[i]) || (i > 0 && !(t_[i] > t_[i - 1])))
      throw std::invalid_argument("speed profile: sample " + std::to_string(i) + " time_s = " +
                                  std::to_string(t_[i]) + ": times must be finite and strictly increasing");
    if (!std::isfinite(v_[i]) || v_[i] < 0.0)
      throw std::invalid_argument("speed profile: sample " + std::to_string(i) + " speed = " +
                                  std::to_string(v_[i]) + " m/s: must be finite and >= 0");
  }
  // Fritsch-Carlson slopes: zero at local extrema, weighted harmonic mean of the secants elsewhere,
  // one-sided secants at the ends. Keeps each cubic inside the range of its two samples.
  const std::size_t n = t_.size();
  slope_.assign(n, 0.0);
  std::vector<double> secant(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) secant[k] = (v_[k + 1] - v_[k]) / (t_[k + 1] - t_[k]);
  slope_[0] = secant[0];
  slope_[n - 1] = secant[n - 2];
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (secant[k - 1] * secant[k] <= 0.0) continue;
    const double h0 = t_[k] - t_[k - 1], h1 = t_[k + 1] - t_[k];
    const double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
    slope_[k] = (w1 + w2) / (w1 / secant[k - 1] + w2 / secant[k]);
  }
  // A one-sided end slope whose secant changes sign at the next sample could overshoot; clamp it.
  if (n > 2 && secant[0] * secant[1] <= 0.0) slope_[0] = 0.0;
  if (n > 2 && secant[n - 2] * secant[n - 3] <= 0.0) slope_[n - 1] = 0.0;
  cumulative_m_.assign(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double h = t_[k + 1] - t_[k];
    // Exact integral of the Hermite cubic over the whole interval.
    cumulative_m_[k + 1] =
        cumulative_m_[k] + h * (0.5 * (v_[k] + v_[k + 1]) + h * (slope_[k] - slope_[k + 1]) / 12.0);
  }
  for (const ProfilePhase& p : phases_) {
    if (!(p.end_s > p.start_s))
      throw std::invalid_argument("speed profile: phase '" + p.name + "' has end <= start");
  }
}

std::size_t SpeedProfile::interval(double t_s) const {
  const auto it = std::upper_bound(t_.begin(), t_.end(), t_s);
  std::size_t k = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  return std::min(k, t_.size() - 2);
}

double SpeedProfile::speed(double t_s) const {
  if (t_s <= t_.front()) return v_.front();
  if (t_s >= t_.back()) return v_.back();
  const std::size_t k = interval(t_s);
  const double h = t_[k + 1] - t_[k], s = (t_s - t_[k]) / h;
  const double s2 = s * s, s3 = s2 * s;
  const double v = (2 * s3 - 3 * s2 + 1) * v_[k] + (s3 - 2 * s2 + s) * h * slope_[k] + (-2 * s3 + 3 * s2) * v_[k + 1] +
                   (s3 - s2) * h * slope_[k + 1];
  return std::max(v, 0.0);  // guards only rounding: the interpolant stays within its samples
}

double SpeedProfile::acceleration(double t_s) const {
  if (t_s < t_.front() || t_s > t_.back()) return 0.0;
  const std::size_t k = interval(t_s);
  const double h = t_[k + 1] - t_[k], s = (t_s - t_[k]) / h;
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * v_[k] + (3 * s2 - 4 * s + 1) * h * slope_[k] + (-6 * s2 + 6 * s) * v_[k + 1] +
          (3 * s2 - 2 * s) * h * slope_[k + 1]) /
         h;
}

double SpeedProfile::distance(double t_s) const {
  if (t_s <= t_.front()) return 0.0;
  if (t_s >= t_.back()) return cumulative_m_.back();
  const std::size_t k = interval(t_s);
  const double h = t_[k + 1] - t_[k], s = (t_s - t_[k]) / h;
  const double s2 = s * s, s3 = s2 * s, s4 = s3 * s;
  return cumulative_m_[k] + h * ((0.5 * s4 - s3 + s) * v_[k] + (0.25 * s4 - 2.0 / 3.0 * s3 + 0.5 * s2) * h * slope_[k] +
                                 (-0.5 * s4 + s3) * v_[k + 1] + (0.25 * s4 - s3 / 3.0) * h * slope_[k + 1]);
}

double SpeedProfile::maxSpeed_mps() const { return *std::max_element(v_.begin(), v_.end()); }

double SpeedProfile::maxSpeed(double t0_s, double t1_s) const {
  if (t1_s < t0_s) std::swap(t0_s, t1_s);
  double vmax = std::max(speed(t0_s), speed(t1_s));
  const auto first = std::upper_bound(t_.begin(), t_.end(), t0_s);
  const auto last = std::lower_bound(t_.begin(), t_.end(), t1_s);
  for (auto it = first; it < last; ++it) vmax = std::max(vmax, v_[static_cast<std::size_t>(it - t_.begin())]);
  return vmax;
}

int phaseIndexAt(const std::vector<ProfilePhase>& phases, double t_s) {
  for (std::size_t i = 0; i < phases.size(); ++i) {
    const bool last = i + 1 == phases.size();
    const double end = last ? phases[i].end_s : phases[i + 1].start_s;
    if (t_s >= phases[i].start_s && (t_s < end || (last && t_s <= end))) return static_cast<int>(i);
  }
  return -1;
}

int SpeedProfile::phaseAt(double t_s) const { return phaseIndexAt(phases_, t_s); }

}  // namespace tread_wear
