#include "tread_wear/planning/candidate_trajectories.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

bool CandidateSetParams::validate(std::string* error) const {
  if (trajectories < 1) return failValidation(error, "trajectories", trajectories, ">= 1");
  if (samples < 1) return failValidation(error, "samples", samples, ">= 1");
  if (!(std::isfinite(time_step_s) && time_step_s > 0.0))
    return failValidation(error, "time_step_s", time_step_s, "finite and > 0 [s]");
  if (!(std::isfinite(max_speed_mps) && max_speed_mps > 2.0))
    return failValidation(error, "max_speed_mps", max_speed_mps, "finite and > 2 [m/s]");
  return true;
}

std::vector<std::vector<TrajectorySample>> generateCandidates(const CandidateSetParams& params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid candidate set parameters: " + error);
  constexpr double kTwoPi = 6.283185307179586;
  std::mt19937 random(params.seed);
  const auto uniform = [&random](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(random); };
  std::vector<std::vector<TrajectorySample>> set(static_cast<std::size_t>(params.trajectories));
  for (auto& trajectory : set) {
    double v = std::min(uniform(2.0, 35.0), params.max_speed_mps);
    const double a_mean = uniform(-1.5, 1.0), a_amp = uniform(0.0, 2.0), t_x = uniform(3.0, 12.0);
    const double phi_x = uniform(0.0, kTwoPi);
    const double ay_mean = uniform(-3.0, 3.0), ay_amp = uniform(0.0, 6.0), t_y = uniform(2.0, 10.0);
    const double phi_y = uniform(0.0, kTwoPi);
    trajectory.resize(static_cast<std::size_t>(params.samples));
    for (int k = 0; k < params.samples; ++k) {
      const double t = k * params.time_step_s;
      const double a_x = std::clamp(a_mean + a_amp * std::sin(kTwoPi * t / t_x + phi_x), -7.5, 4.5);
      const double a_y = std::clamp(ay_mean + ay_amp * std::sin(kTwoPi * t / t_y + phi_y), -8.5, 8.5);
      trajectory[static_cast<std::size_t>(k)] = {t, v, a_x, std::clamp(a_y / std::max(v * v, 1.0), -0.2, 0.2)};
      v = std::clamp(v + a_x * params.time_step_s, 0.0, params.max_speed_mps);
    }
  }
  return set;
}

}  // namespace tread_wear
