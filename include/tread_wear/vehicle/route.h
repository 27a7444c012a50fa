#pragma once
/// @file route.h
/// A deterministic road route for a speed profile: path curvature kappa(s) of the vehicle's centre of
/// gravity over the distance travelled s, made of straights and curve events whose radii respect a
/// lateral-acceleration limit at the speeds the profile drives through them.
///
/// Construction (RouteBuilder::build), walking along the distance of the profile:
///   1. A straight whose length is drawn from the band of the local speed (urban / rural / motorway).
///   2. A curve event chosen by the speed band of the next stretch:
///        urban     (v_max <= urban_max_speed):  a junction turn (90 deg, nominal radius junction_radius_m),
///                  or, when the car is slow enough for it, a roundabout: a right entry deflection, a left ring
///                  arc of radius roundabout_radius_m to the 1st/2nd/3rd exit (90/180/270 deg net) and a right
///                  exit deflection (right-hand traffic, counter-clockwise ring);
///        rural     (v_max <= rural_max_speed):  a bend of 20-60 deg with nominal radius 120-300 m;
///        motorway: a curve of 10-30 deg with nominal radius 700-1500 m.
///      Directions alternate at random. Each arc has clothoid transitions (curvature linear in s) of
///      length min(R/3, angle R), so the curvature is continuous.
///   3. Radius consistent with the speeds: R = max(R_nominal, v_max^2 / a_y_limit), where v_max is the
///      largest profile speed while the car is inside the event; iterated because a larger R lengthens the
///      event. Hence |v^2 kappa| <= a_y_limit at every time of the drive, by construction.
/// Draws use std::mt19937 (fully specified by the C++ standard) mapped to [0, 1) by hand, so a seed gives
/// the same route on every platform. Sign: ISO 8855, kappa > 0 turning left (operating_point.h).
/// Limits: flat road (no grade, no banking); no lane changes; a car standing still keeps its position.

#include <cstdint>
#include <string>
#include <vector>

#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

struct RouteParams {
  double lateral_accel_limit_mps2 = 3.0;  ///< a_y limit that sets the smallest radius at speed [m/s^2], > 0
  std::uint32_t seed = 20240601;          ///< random stream of straight lengths, angles and directions [-]
  double urban_max_speed_mps = 60.0 / 3.6;   ///< events with v_max up to this are urban [m/s]
  double rural_max_speed_mps = 100.0 / 3.6;  ///< events with v_max up to this are rural, above: motorway [m/s]
  double junction_radius_m = 12.0;        ///< nominal radius of a 90 deg junction turn [m], > 0
  double roundabout_radius_m = 15.0;      ///< radius of the driven ring path [m], > 0
  double roundabout_deflection_radius_m = 20.0;  ///< radius of the entry/exit deflections [m], > 0
  double roundabout_share = 0.4;          ///< share of urban events that are roundabouts when slow enough [-]

  bool validate(std::string* error) const;
};

enum class RouteEventKind { kStraight = 0, kJunctionTurn = 1, kRoundabout = 2, kRuralBend = 3, kMotorwayCurve = 4 };
const char* routeEventKindName(RouteEventKind kind);

/// One piece of the route with curvature linear in s from kappa_start to kappa_end.
struct RouteSegment {
  double s_start_m = 0.0;        ///< distance at the start [m]
  double length_m = 0.0;         ///< [m], > 0
  double kappa_start_per_m = 0.0;  ///< curvature at the start [1/m], > 0 left
  double kappa_end_per_m = 0.0;    ///< curvature at the end [1/m]
  int event = -1;                ///< index into Route::events(), -1 for straights
};

/// A curve event as built (for documentation and plots).
struct RouteEvent {
  RouteEventKind kind = RouteEventKind::kStraight;
  double s_start_m = 0.0;     ///< [m]
  double length_m = 0.0;      ///< [m]
  double t_start_s = 0.0;     ///< profile time at which the car enters it [s]
  double radius_m = 0.0;      ///< radius of the main arc [m] (ring radius for roundabouts)
  double angle_rad = 0.0;     ///< net heading change [rad], > 0 left
  double v_max_mps = 0.0;     ///< largest speed inside the event [m/s]
};

class Route {
 public:
  Route() = default;
  Route(std::vector<RouteSegment> segments, std::vector<RouteEvent> events);

  /// Curvature of the CoG path at distance s [1/m]; 0 beyond the end.
  double curvature(double s_m) const;
  double length_m() const { return segments_.empty() ? 0.0 : segments_.back().s_start_m + segments_.back().length_m; }
  const std::vector<RouteSegment>& segments() const { return segments_; }
  const std::vector<RouteEvent>& events() const { return events_; }

 private:
  std::vector<RouteSegment> segments_;
  std::vector<RouteEvent> events_;
};

/// Builds the route for a profile. @throw std::invalid_argument for invalid params
Route buildRoute(const SpeedProfile& profile, const RouteParams& params);

}  // namespace tread_wear
