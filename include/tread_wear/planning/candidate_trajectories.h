#pragma once
/// @file candidate_trajectories.h
/// Seeded sets of realistic candidate trajectories of a passenger car, the kind a local planner scores: cruising,
/// accelerating, braking to a stop, steady curves and lane changes, 100 samples over 10 s by default. The benchmark,
/// the map's accuracy test and the tool's --generate use the same sets, so their numbers refer to the same
/// trajectories.
///
/// Per trajectory (uniform draws from std::mt19937 seeded with `seed`, each trajectory in turn):
///   a_x(t) = clamp(a_mean + a_amp sin(2 pi t / T_x + phi_x), -7.5, 4.5)          [m/s^2]
///   v_k+1  = clamp(v_k + a_x(t_k) dt, 0, max_speed)   from v_0                     [m/s]  (stops stay stopped)
///   a_y(t) = clamp(a_y,mean + a_y,amp sin(2 pi t / T_y + phi_y), -8.5, 8.5)         [m/s^2] (curve + lane change)
///   kappa  = clamp(a_y / max(v^2, 1 m^2/s^2), -0.2, 0.2)                            [1/m]
/// with v_0 in [2, 35] m/s, a_mean in [-1.5, 1], a_amp in [0, 2] m/s^2, T_x in [3, 12] s, a_y,mean in [-3, 3],
/// a_y,amp in [0, 6] m/s^2, T_y in [2, 10] s. So every sample lies inside the default map axes (wear_map.h).

#include <cstdint>
#include <string>
#include <vector>

#include "tread_wear/planning/trajectory_cost.h"

namespace tread_wear {

struct CandidateSetParams {
  int trajectories = 100;      ///< candidates [-], >= 1
  int samples = 100;           ///< samples per candidate [-], >= 1
  double time_step_s = 0.1;    ///< sample spacing [s], > 0
  double max_speed_mps = 44.0; ///< speed ceiling of the profiles [m/s], > 2
  std::uint32_t seed = 24;     ///< std::mt19937 seed [-]

  bool validate(std::string* error) const;
};

/// The candidate set. @throw std::invalid_argument naming the field for invalid params.
std::vector<std::vector<TrajectorySample>> generateCandidates(const CandidateSetParams& params);

}  // namespace tread_wear
