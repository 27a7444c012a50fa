#pragma once
/// @file driving_style.h
/// A driving style as an envelope of accelerations, and a cycle's route driven within it: the same route (curvature
/// over distance s, built once from the profile, route.h) and the same stops (at the same s, with the profile's
/// dwell times), driven by a driver who accelerates, brakes and corners up to the envelope. Calm and aggressive
/// drives of a cycle therefore cover the same distance on the same road and differ in time, a_x and a_y
/// (docs/drive.md, "Scenarios").
///
/// Speed over distance, on a grid of nodes (every grid_step_m, every stop and every route segment boundary):
///   1. profile speed v_p(s): the profile's speed when it first reaches s; stops: runs of profile samples at 0;
///   2. desired speed v_d(s): the largest v_p within +-target_window_m/2 of s inside the same microtrip (between two
///      stops): the speed the profile holds next, which the driver aims for, reached at the driver's own a_x;
///   3. curve cap v_d^2 <= a_y,max / max|kappa| over s +- delta, delta = smoothing_s v_top + 2 grid steps (v_top the
///      largest v_d): the car is at curve speed from delta before a curve to delta after it, which keeps a_y within
///      the envelope after the smoothing below;
///   4. driven speed: forward pass v_{i+1}^2 <= v_i^2 + 2 a_max ds, backward pass v_i^2 <= v_{i+1}^2 + 2 d_max ds,
///      v = 0 at the stops; between nodes constant acceleration (v^2 linear in s);
///   5. over time: the cells of constant acceleration, the dwell at each stop, smoothed by the moving average of
///      drive_motion.h over smoothing_s. The average keeps a_x in [-d_max, a_max], v^2 |kappa| <= a_y,max (step 3),
///      the stops (dwells >= smoothing_s) and the distance, and makes a_x continuous with jerk
///      <= (a_max + d_max) / smoothing_s.
/// Phases are carried over by distance: a phase boundary at distance s (or inside a stop) falls at the time the
/// drive reaches s (or at the same offset into that stop).

#include <string>
#include <vector>

#include "tread_wear/vehicle/drive_motion.h"
#include "tread_wear/vehicle/route.h"
#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

/// Largest value of an envelope's accelerations: 0.8 g, about the friction limit of a passenger-car tire on dry
/// asphalt [m/s^2] (as kMaxManoeuvreAccel_mps2).
constexpr double kMaxEnvelopeAccel_mps2 = 8.0;

/// A driver's envelope. Defaults: the style "normal".
struct DrivingEnvelope {
  double max_accel_mps2 = 1.7;          ///< a_max [m/s^2], in (0, 8]
  double max_decel_mps2 = 2.5;          ///< d_max, a positive number [m/s^2], in (0, 8]
  double max_lateral_accel_mps2 = 3.0;  ///< a_y,max [m/s^2], in (0, 8]

  bool validate(std::string* error) const;
};

/// The named styles (docs/drive.md, "Scenarios", for the numbers and where they come from):
///   calm       a_max 1.0, d_max 1.5, a_y,max 2.0 m/s^2
///   normal     a_max 1.7, d_max 2.5, a_y,max 3.0 m/s^2
///   aggressive a_max 3.0, d_max 4.0, a_y,max 4.5 m/s^2
/// False for another name.
bool drivingStyle(const std::string& name, DrivingEnvelope* envelope);

/// How the envelope drive is built (steps above).
struct EnvelopeDriveParams {
  double target_window_m = 200.0;  ///< window of the desired speed [m], >= 0 (0: the profile's own speed)
  double grid_step_m = 0.5;        ///< node spacing [m], > 0
  double smoothing_s = 1.0;        ///< tau of the moving average [s], >= 0, at most the shortest stop's dwell

  bool validate(std::string* error) const;
};

struct EnvelopeDrive {
  SpeedTrace trace;                  ///< the drive over the route, from time 0
  std::vector<ProfilePhase> phases;  ///< the profile's phases on the drive's time [s]
};

/// The profile's route driven within the envelope. @throw std::invalid_argument naming the field for invalid params
/// or envelope
EnvelopeDrive driveWithinEnvelope(const SpeedProfile& profile, const Route& route, const DrivingEnvelope& envelope,
                                  const EnvelopeDriveParams& params = {});

}  // namespace tread_wear
