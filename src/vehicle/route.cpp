#include "tread_wear/vehicle/route.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

/// Portable uniform draws: mt19937 is specified bit for bit; the standard distributions are not.
class Draw {
 public:
  explicit Draw(std::uint32_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(engine_()) / 4294967296.0); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  int pick(int n) { return std::min(n - 1, static_cast<int>(uniform(0.0, n))); }

 private:
  std::mt19937 engine_;
};

/// First time at which the car has covered distance s (the profile's distance is non-decreasing).
double timeAtDistance(const SpeedProfile& profile, double s_m) {
  double lo = profile.startTime_s(), hi = profile.endTime_s();
  if (s_m <= 0.0) return lo;
  if (s_m >= profile.totalDistance_m()) return hi;
  for (int i = 0; i < 60 && hi - lo > 1e-6; ++i) {
    const double mid = 0.5 * (lo + hi);
    (profile.distance(mid) >= s_m ? hi : lo) = mid;
  }
  return hi;
}

/// One circular arc of an event with its clothoid transitions.
struct Arc {
  double angle_rad;  ///< signed heading change, > 0 left
  double radius_m;   ///< > 0
};

double transitionLength(const Arc& arc) {
  return std::min(arc.radius_m / 3.0, std::fabs(arc.angle_rad) * arc.radius_m);
}
double arcLength(const Arc& arc) { return std::fabs(arc.angle_rad) * arc.radius_m + transitionLength(arc); }

}  // namespace

const char* routeEventKindName(RouteEventKind kind) {
  switch (kind) {
    case RouteEventKind::kStraight: return "straight";
    case RouteEventKind::kJunctionTurn: return "junction_turn";
    case RouteEventKind::kRoundabout: return "roundabout";
    case RouteEventKind::kRuralBend: return "rural_bend";
    case RouteEventKind::kMotorwayCurve: return "motorway_curve";
  }
  return "unknown";
}

bool RouteParams::validate(std::string* error) const {
  if (!(lateral_accel_limit_mps2 > 0.0) || !std::isfinite(lateral_accel_limit_mps2))
    return failValidation(error, "lateral_accel_limit_mps2", lateral_accel_limit_mps2, "finite and > 0");
  if (!(urban_max_speed_mps > 0.0) || !std::isfinite(urban_max_speed_mps))
    return failValidation(error, "urban_max_speed_mps", urban_max_speed_mps, "finite and > 0");
  if (!(rural_max_speed_mps > urban_max_speed_mps) || !std::isfinite(rural_max_speed_mps))
    return failValidation(error, "rural_max_speed_mps", rural_max_speed_mps, "finite and > urban_max_speed_mps");
  if (!(junction_radius_m > 0.0) || !std::isfinite(junction_radius_m))
    return failValidation(error, "junction_radius_m", junction_radius_m, "finite and > 0");
  if (!(roundabout_radius_m > 0.0) || !std::isfinite(roundabout_radius_m))
    return failValidation(error, "roundabout_radius_m", roundabout_radius_m, "finite and > 0");
  if (!(roundabout_deflection_radius_m > 0.0) || !std::isfinite(roundabout_deflection_radius_m))
    return failValidation(error, "roundabout_deflection_radius_m", roundabout_deflection_radius_m, "finite and > 0");
  if (!(roundabout_share >= 0.0 && roundabout_share <= 1.0))
    return failValidation(error, "roundabout_share", roundabout_share, "in [0, 1]");
  return true;
}

Route::Route(std::vector<RouteSegment> segments, std::vector<RouteEvent> events)
    : segments_(std::move(segments)), events_(std::move(events)) {}

double Route::curvature(double s_m) const {
  if (segments_.empty() || s_m < 0.0 || s_m >= length_m()) return 0.0;
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), s_m,
                                   [](double s, const RouteSegment& seg) { return s < seg.s_start_m; });
  const RouteSegment& seg = *(it - 1);
  const double u = (s_m - seg.s_start_m) / seg.length_m;
  return seg.kappa_start_per_m + u * (seg.kappa_end_per_m - seg.kappa_start_per_m);
}

Route buildRoute(const SpeedProfile& profile, const RouteParams& params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid route parameters: " + error);
  constexpr double kDeg = units::kDegree;
  constexpr double kApproach_m = 60.0;  // stretch whose speed decides the kind of the next event [m]
  constexpr int kMaxRadiusIterations = 50;
  const double a_lim = params.lateral_accel_limit_mps2;
  const double total = profile.totalDistance_m();
  Draw draw(params.seed);
  std::vector<RouteSegment> segments;
  std::vector<RouteEvent> events;

  auto addSegment = [&](double s, double length, double k0, double k1, int event) {
    if (length > 0.0) segments.push_back({s, length, k0, k1, event});
  };

  double s = 0.0;
  while (s < total) {
    // Straight, its length from the speed band of the stretch ahead.
    const double v_ahead = profile.maxSpeed(timeAtDistance(profile, s), timeAtDistance(profile, s + 200.0));
    double straight = 0.0;
    if (v_ahead <= params.urban_max_speed_mps) straight = draw.uniform(80.0, 250.0);
    else if (v_ahead <= params.rural_max_speed_mps) straight = draw.uniform(300.0, 900.0);
    else straight = draw.uniform(800.0, 2500.0);
    addSegment(s, straight, 0.0, 0.0, -1);
    s += straight;
    if (s >= total) break;

    // Curve event of the band of its approach speed.
    const double t0 = timeAtDistance(profile, s);
    const double v_approach = profile.maxSpeed(t0, timeAtDistance(profile, s + kApproach_m));
    RouteEvent event;
    std::vector<Arc> arcs;
    arcs.reserve(3);  // at most three arcs (a roundabout); also keeps GCC 12 from a false -Wnonnull on the assignments
    const double side = draw.chance(0.5) ? 1.0 : -1.0;
    if (v_approach <= params.urban_max_speed_mps) {
      const bool slow_enough = v_approach * v_approach <= a_lim * params.roundabout_radius_m;
      if (draw.chance(params.roundabout_share) && slow_enough) {
        event.kind = RouteEventKind::kRoundabout;
        const double exit_angle = 90.0 * kDeg * (1 + draw.pick(3));
        const double deflection = 25.0 * kDeg;
        arcs = {{-deflection, params.roundabout_deflection_radius_m},
                {exit_angle + 2.0 * deflection, params.roundabout_radius_m},
                {-deflection, params.roundabout_deflection_radius_m}};
      } else {
        event.kind = RouteEventKind::kJunctionTurn;
        arcs = {{side * 90.0 * kDeg, params.junction_radius_m}};
      }
    } else if (v_approach <= params.rural_max_speed_mps) {
      event.kind = RouteEventKind::kRuralBend;
      arcs = {{side * draw.uniform(20.0, 60.0) * kDeg, draw.uniform(120.0, 300.0)}};
    } else {
      event.kind = RouteEventKind::kMotorwayCurve;
      arcs = {{side * draw.uniform(10.0, 30.0) * kDeg, draw.uniform(700.0, 1500.0)}};
    }

    // Scale all radii until the tightest satisfies v_max^2 / R <= a_lim over the whole event.
    double min_radius = arcs.front().radius_m;
    for (const Arc& a : arcs) min_radius = std::min(min_radius, a.radius_m);
    auto eventLength = [&](double scale) {
      double length = 0.0;
      for (const Arc& a : arcs) length += scale * arcLength(a);
      return length;
    };
    double scale = 1.0, v_max = 0.0;
    bool consistent = false;
    for (int it = 0; it < kMaxRadiusIterations && !consistent; ++it) {
      v_max = profile.maxSpeed(t0, timeAtDistance(profile, s + eventLength(scale)));
      const double required = v_max * v_max / a_lim;
      consistent = required <= scale * min_radius;
      if (!consistent) scale = required / min_radius;
    }
    if (!consistent) {  // the drive's top speed bounds every window
      v_max = profile.maxSpeed_mps();
      scale = std::max(scale, v_max * v_max / a_lim / min_radius);
    }

    event.s_start_m = s;
    event.t_start_s = t0;
    event.v_max_mps = v_max;
    event.radius_m = scale * (event.kind == RouteEventKind::kRoundabout ? arcs[1].radius_m : arcs[0].radius_m);
    const int index = static_cast<int>(events.size());
    for (const Arc& a : arcs) {
      const double radius = scale * a.radius_m;
      const Arc scaled{a.angle_rad, radius};
      const double kappa = (a.angle_rad > 0.0 ? 1.0 : -1.0) / radius;
      const double transition = transitionLength(scaled);
      const double constant = std::fabs(a.angle_rad) * radius - transition;
      addSegment(s, transition, 0.0, kappa, index);
      addSegment(s + transition, constant, kappa, kappa, index);
      addSegment(s + transition + constant, transition, kappa, 0.0, index);
      s += constant + 2.0 * transition;
      event.angle_rad += a.angle_rad;
    }
    event.length_m = s - event.s_start_m;
    events.push_back(event);
  }
  return Route(std::move(segments), std::move(events));
}

}  // namespace tread_wear
