#include "tread_wear/vehicle/driving_style.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

static_assert(kMaxEnvelopeAccel_mps2 == 8.0, "the constraint text below names the bound");
constexpr const char* kSaneAccel = "finite, > 0 and <= 8 (0.8 g)";
bool saneAccel(double v) { return std::isfinite(v) && v > 0.0 && v <= kMaxEnvelopeAccel_mps2; }

/// Nodes closer than this are one node [m].
constexpr double kSameNode_m = 1e-6;

/// A stop of the profile: a run of samples at standstill.
struct Stop {
  double s_m;        ///< where [m]
  double arrival_s;  ///< profile time of its first sample [s]
  double dwell_s;    ///< profile time standing [s]
};

std::vector<Stop> profileStops(const SpeedProfile& profile) {
  const std::vector<double>& t = profile.times_s();
  const std::vector<double>& v = profile.speeds_mps();
  std::vector<Stop> stops;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] > 0.0) continue;
    std::size_t j = i;
    while (j + 1 < v.size() && v[j + 1] <= 0.0) ++j;
    stops.push_back({profile.distance(t[i]), t[i], t[j] - t[i]});
    i = j;
  }
  return stops;
}

/// First profile time in [t_lo, end] at which the profile has covered s (its distance does not decrease).
double firstTimeAt(const SpeedProfile& profile, double s_m, double t_lo) {
  double lo = t_lo, hi = profile.endTime_s();
  if (profile.distance(lo) >= s_m) return lo;
  for (int i = 0; i < 100 && hi - lo > 1e-9; ++i) {
    const double mid = 0.5 * (lo + hi);
    (profile.distance(mid) >= s_m ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

bool DrivingEnvelope::validate(std::string* error) const {
  if (!saneAccel(max_accel_mps2)) return failValidation(error, "max_accel_mps2", max_accel_mps2, kSaneAccel);
  if (!saneAccel(max_decel_mps2)) return failValidation(error, "max_decel_mps2", max_decel_mps2, kSaneAccel);
  if (!saneAccel(max_lateral_accel_mps2))
    return failValidation(error, "max_lateral_accel_mps2", max_lateral_accel_mps2, kSaneAccel);
  return true;
}

bool drivingStyle(const std::string& name, DrivingEnvelope* envelope) {
  if (name == "calm") *envelope = {1.0, 1.5, 2.0};
  else if (name == "normal") *envelope = {1.7, 2.5, 3.0};
  else if (name == "aggressive") *envelope = {3.0, 4.0, 4.5};
  else return false;
  return true;
}

bool EnvelopeDriveParams::validate(std::string* error) const {
  if (!(std::isfinite(target_window_m) && target_window_m >= 0.0))
    return failValidation(error, "target_window_m", target_window_m, "finite and >= 0");
  if (!(std::isfinite(grid_step_m) && grid_step_m > 0.0))
    return failValidation(error, "grid_step_m", grid_step_m, "finite and > 0");
  if (!(std::isfinite(smoothing_s) && smoothing_s >= 0.0))
    return failValidation(error, "smoothing_s", smoothing_s, "finite and >= 0");
  return true;
}

EnvelopeDrive driveWithinEnvelope(const SpeedProfile& profile, const Route& route, const DrivingEnvelope& envelope,
                                  const EnvelopeDriveParams& params) {
  std::string error;
  if (!envelope.validate(&error)) throw std::invalid_argument("invalid driving envelope: " + error);
  if (!params.validate(&error)) throw std::invalid_argument("invalid envelope drive parameters: " + error);
  const double total = profile.totalDistance_m();
  if (!(total > 0.0)) throw std::invalid_argument("envelope drive: the profile covers no distance");
  std::vector<Stop> stops = profileStops(profile);

  // Nodes: the grid, the stops and the route's segment boundaries (|kappa| is linear between nodes, so its largest
  // value over a stretch is at a node).
  std::vector<double> s;
  const std::size_t n_grid = static_cast<std::size_t>(std::ceil(total / params.grid_step_m));
  for (std::size_t i = 0; i <= n_grid; ++i) s.push_back(total * static_cast<double>(i) / static_cast<double>(n_grid));
  for (const Stop& stop : stops) s.push_back(stop.s_m);
  for (const RouteSegment& seg : route.segments())
    if (seg.s_start_m > 0.0 && seg.s_start_m < total) s.push_back(seg.s_start_m);
  std::sort(s.begin(), s.end());
  s.erase(std::unique(s.begin(), s.end(), [](double a, double b) { return b - a < kSameNode_m; }), s.end());
  const std::size_t n = s.size();
  std::vector<int> stop_at(n, -1);  // index into stops, or -1
  for (std::size_t k = 0; k < stops.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(std::lower_bound(s.begin(), s.end(), stops[k].s_m - kSameNode_m) -
                                                    s.begin());
    if (stop_at[i] >= 0) {  // two stops without distance between them: one stop with both dwells
      stops[static_cast<std::size_t>(stop_at[i])].dwell_s += stops[k].dwell_s;
      continue;
    }
    stop_at[i] = static_cast<int>(k);
  }

  // 1-2. Profile speed where it first reaches each node, then the desired speed within each microtrip.
  std::vector<double> v_profile(n, 0.0);
  double t = profile.startTime_s();
  for (std::size_t i = 0; i < n; ++i) {
    t = firstTimeAt(profile, s[i], t);
    v_profile[i] = stop_at[i] >= 0 ? 0.0 : profile.speed(t);
  }
  const double half_window = params.target_window_m / 2.0;
  std::vector<double> v_desired(n, 0.0);
  double v_top = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (stop_at[i] >= 0) continue;
    double v = v_profile[i];
    for (std::size_t j = i; j > 0 && stop_at[j - 1] < 0 && s[i] - s[j - 1] <= half_window; --j)
      v = std::max(v, v_profile[j - 1]);
    for (std::size_t j = i + 1; j < n && stop_at[j] < 0 && s[j] - s[i] <= half_window; ++j)
      v = std::max(v, v_profile[j]);
    v_desired[i] = v;
    v_top = std::max(v_top, v);
  }

  // 3. Upper bound of v^2 at each node: desired speed, curve cap over +-delta, 0 at the stops.
  double max_spacing = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) max_spacing = std::max(max_spacing, s[i + 1] - s[i]);
  const double delta = params.smoothing_s * v_top + 2.0 * max_spacing;
  std::vector<double> abs_kappa(n);
  for (std::size_t i = 0; i < n; ++i) abs_kappa[i] = std::fabs(route.curvature(s[i]));
  std::vector<double> w(n);  // v^2 [m^2/s^2]
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (s[i] - s[lo] > delta) ++lo;
    while (hi + 1 < n && s[hi + 1] - s[i] <= delta) ++hi;
    const double kappa = *std::max_element(abs_kappa.begin() + static_cast<std::ptrdiff_t>(lo),
                                           abs_kappa.begin() + static_cast<std::ptrdiff_t>(hi) + 1);
    const double cap = kappa > 0.0 ? envelope.max_lateral_accel_mps2 / kappa : std::numeric_limits<double>::infinity();
    w[i] = stop_at[i] >= 0 ? 0.0 : std::min(v_desired[i] * v_desired[i], cap);
  }

  // 4. Acceleration- and deceleration-limited passes.
  for (std::size_t i = 0; i + 1 < n; ++i)
    w[i + 1] = std::min(w[i + 1], w[i] + 2.0 * envelope.max_accel_mps2 * (s[i + 1] - s[i]));
  for (std::size_t i = n - 1; i > 0; --i)
    w[i - 1] = std::min(w[i - 1], w[i] + 2.0 * envelope.max_decel_mps2 * (s[i] - s[i - 1]));

  // 5. Cells over time: the dwell at each stop, then constant acceleration to the next node.
  std::vector<SpeedCell> cells;
  std::vector<double> arrival(n), departure(n);
  double clock = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    arrival[i] = clock;
    if (stop_at[i] >= 0 && stops[static_cast<std::size_t>(stop_at[i])].dwell_s > 0.0) {
      cells.push_back({stops[static_cast<std::size_t>(stop_at[i])].dwell_s, 0.0});
      clock += cells.back().duration_s;
    }
    departure[i] = clock;
    if (i + 1 == n) break;
    const double ds = s[i + 1] - s[i], v0 = std::sqrt(w[i]), v1 = std::sqrt(w[i + 1]);
    if (!(v0 + v1 > 0.0))
      throw std::invalid_argument("envelope drive: no speed between the stops at " + std::to_string(s[i]) + " and " +
                                  std::to_string(s[i + 1]) + " m");
    cells.push_back({2.0 * ds / (v0 + v1), (w[i + 1] - w[i]) / (2.0 * ds)});
    clock += cells.back().duration_s;
  }

  // Phases by distance: the drive's time at a profile time's distance, or the same offset into its stop.
  auto driveTime = [&](double t_profile) {
    const double s_at = profile.distance(t_profile);
    for (std::size_t i = 0; i < n; ++i) {
      if (stop_at[i] < 0) continue;
      const Stop& stop = stops[static_cast<std::size_t>(stop_at[i])];
      if (std::fabs(stop.s_m - s_at) < kSameNode_m && t_profile >= stop.arrival_s &&
          t_profile <= stop.arrival_s + stop.dwell_s)
        return arrival[i] + (t_profile - stop.arrival_s);
    }
    const std::size_t k = std::min<std::size_t>(
        n - 2, static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), s_at) - s.begin()) - 1);
    const double ds = s_at - s[k], v0 = std::sqrt(w[k]), a = (w[k + 1] - w[k]) / (2.0 * (s[k + 1] - s[k]));
    // Time to cover ds from v0 at constant a, in the form without cancellation.
    const double root = std::sqrt(std::max(0.0, v0 * v0 + 2.0 * a * ds));
    return departure[k] + (v0 + root > 0.0 ? 2.0 * ds / (v0 + root) : 0.0);
  };
  std::vector<ProfilePhase> phases;
  for (const ProfilePhase& p : profile.phases()) phases.push_back({p.name, driveTime(p.start_s), driveTime(p.end_s)});

  return {SpeedTrace(std::sqrt(w.front()), cells, clock, params.smoothing_s, route), phases};
}

}  // namespace tread_wear
