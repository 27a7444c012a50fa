#include "tread_wear/vehicle/driving_programme.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

constexpr double kPi = 3.14159265358979323846;
/// Distances below this are rounding of the data's decimals (sector lengths to 0.1 m, speeds to 1e-15) [m].
constexpr double kDistanceRounding_m = 1e-6;
/// Sampling of the built drive for its largest lateral acceleration [s].
constexpr double kStatsStep_s = 0.1;
/// Distance grid of the corner speed bound (CellTrace::capped) [m].
constexpr double kCapGrid_m = 0.5;

bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

/// One piece of a corner's curvature over distance: 0 -> kappa over a clothoid, kappa on the arc, kappa -> 0.
struct CornerShape {
  double start_m, transition_m, arc_m, kappa_per_m;
  double end_m() const { return start_m + 2.0 * transition_m + arc_m; }
  double curvature(double s) const {
    const double u = s - start_m;
    if (u <= 0.0 || u >= 2.0 * transition_m + arc_m) return 0.0;
    if (u < transition_m) return kappa_per_m * u / transition_m;
    if (u <= transition_m + arc_m) return kappa_per_m;
    return kappa_per_m * (2.0 * transition_m + arc_m - u) / transition_m;
  }
};

/// The speed trace as cells, with the distance at each cell boundary, so that the speed over a stretch of road is
/// known before the route is built.
class CellTrace {
 public:
  explicit CellTrace(double start_speed_mps) : v_{start_speed_mps}, s_{0.0} {}

  double speed() const { return v_.back(); }
  double distance() const { return s_.back(); }
  const std::vector<SpeedCell>& cells() const { return cells_; }
  double duration() const { return duration_s_; }

  void changeSpeed(double v1, double rate_mps2) {
    const double v0 = v_.back();
    if (std::fabs(v1 - v0) < 1e-12) return;
    const double a = v1 > v0 ? rate_mps2 : -rate_mps2;
    push({(v1 - v0) / a, a}, v1, (v1 * v1 - v0 * v0) / (2.0 * a));
  }
  void cruise(double distance_m) {
    if (distance_m <= kDistanceRounding_m) return;
    const double v = v_.back();
    if (!(v > 0.0))
      throw std::invalid_argument("driving programme: a Constant manoeuvre of " + std::to_string(distance_m) +
                                  " m at standstill");
    push({distance_m / v, 0.0}, v, distance_m);
  }
  /// The same drive with the speed at most cap(s) (a list of [s0, s1, v_max]), reached by braking at brake
  /// and left by accelerating at accel: the distance-domain forward-backward bound of lap-time simulation, on a
  /// grid of ds (v^2 is linear in s within a cell of constant acceleration, so the grid only moves cell edges).
  CellTrace capped(const std::vector<std::array<double, 3>>& caps, double brake_mps2, double accel_mps2,
                   double ds_m) const {
    const std::size_t n = static_cast<std::size_t>(std::ceil(distance() / ds_m));
    std::vector<double> s(n + 1), v2(n + 1);
    std::size_t k = 0;
    for (std::size_t i = 0; i <= n; ++i) {
      s[i] = std::min(distance(), i * ds_m);
      while (k + 1 < cells_.size() && s_[k + 1] < s[i]) ++k;
      const double v = cells_.empty() ? v_.front() : speedAt(k, s[i]);
      v2[i] = v * v;
    }
    // The corners' bound alone, with its braking before and acceleration after; the programme's own manoeuvres
    // keep their constants.
    std::vector<double> bound(n + 1, std::numeric_limits<double>::infinity());
    for (const auto& cap : caps)
      for (std::size_t i = 0; i <= n; ++i)
        if (s[i] >= cap[0] && s[i] <= cap[1]) bound[i] = std::min(bound[i], cap[2] * cap[2]);
    for (std::size_t i = n; i-- > 0;) bound[i] = std::min(bound[i], bound[i + 1] + 2.0 * brake_mps2 * (s[i + 1] - s[i]));
    for (std::size_t i = 1; i <= n; ++i)
      bound[i] = std::min(bound[i], bound[i - 1] + 2.0 * accel_mps2 * (s[i] - s[i - 1]));
    bool binds = false;
    for (std::size_t i = 0; i <= n; ++i) {
      binds = binds || bound[i] < v2[i];
      v2[i] = std::min(v2[i], bound[i]);
    }
    if (!binds) return *this;
    CellTrace out(std::sqrt(v2[0]));
    for (std::size_t i = 0; i < n; ++i) {
      const double ds = s[i + 1] - s[i], v0 = std::sqrt(v2[i]), v1 = std::sqrt(v2[i + 1]);
      if (!(ds > 0.0) || v0 + v1 <= 0.0) continue;
      out.push({2.0 * ds / (v0 + v1), (v2[i + 1] - v2[i]) / (2.0 * ds)}, v1, ds);
    }
    return out;
  }
  /// Largest speed while the distance driven is in [s0, s1] (speed is monotone within a cell).
  double maxSpeed(double s0, double s1) const {
    double best = 0.0;
    for (std::size_t k = 0; k + 1 < s_.size(); ++k) {
      if (s_[k + 1] < s0 || s_[k] > s1) continue;
      best = std::max(best, std::max(speedAt(k, std::max(s0, s_[k])), speedAt(k, std::min(s1, s_[k + 1]))));
    }
    return best;
  }

 private:
  void push(SpeedCell cell, double v1, double ds) {
    cells_.push_back(cell);
    v_.push_back(v1);
    s_.push_back(s_.back() + ds);
    duration_s_ += cell.duration_s;
  }
  double speedAt(std::size_t k, double s) const {
    const double a = cells_[k].accel_mps2;
    return std::sqrt(std::max(0.0, v_[k] * v_[k] + 2.0 * a * (s - s_[k])));
  }
  std::vector<SpeedCell> cells_;
  std::vector<double> v_, s_;
  double duration_s_ = 0.0;
};

/// Drives one pass of a sector's manoeuvre sequence over pass_m, carrying *debt_m: distance the previous
/// manoeuvres overran, which this pass's Constant manoeuvres give back.
void drivePass(const std::vector<const ProgrammeManoeuvre*>& sequence, double pass_m, double* debt_m,
               CellTrace* trace) {
  double used_m = *debt_m, speed = trace->speed();
  int constants = 0;
  for (const ProgrammeManoeuvre* m : sequence) {
    if (m->kind == ProgrammeManoeuvreKind::kConstant) {
      ++constants;
      continue;
    }
    const double rate = m->kind == ProgrammeManoeuvreKind::kAcceleration ? m->accel_mps2 : m->decel_mps2;
    used_m += std::fabs(m->end_speed_mps * m->end_speed_mps - speed * speed) / (2.0 * rate);
    speed = m->end_speed_mps;
  }
  const double rest_m = pass_m - used_m;
  *debt_m = std::max(0.0, -rest_m);
  const double share_m = constants > 0 ? std::max(0.0, rest_m) / constants : 0.0;
  for (const ProgrammeManoeuvre* m : sequence) {
    switch (m->kind) {
      case ProgrammeManoeuvreKind::kConstant:
        trace->cruise(share_m);
        break;
      case ProgrammeManoeuvreKind::kAcceleration:
        if (m->end_speed_mps < trace->speed() - 1e-9)
          throw std::invalid_argument("driving programme: acceleration " + m->sector_id + " to a lower speed");
        trace->changeSpeed(m->end_speed_mps, m->accel_mps2);
        break;
      case ProgrammeManoeuvreKind::kDeceleration:
        if (m->end_speed_mps > trace->speed() + 1e-9)
          throw std::invalid_argument("driving programme: deceleration " + m->sector_id + " to a higher speed");
        trace->changeSpeed(m->end_speed_mps, m->decel_mps2);
        break;
    }
  }
  if (constants == 0) trace->cruise(std::max(0.0, rest_m));  // a sector not filled by its manoeuvres is cruised
}

/// The manoeuvres of `section` in `sector`, in order.
std::vector<const ProgrammeManoeuvre*> sectorSequence(const ProgrammeSection& section, const std::string& sector) {
  std::vector<const ProgrammeManoeuvre*> sequence;
  for (const ProgrammeManoeuvre& m : section.manoeuvres)
    if (m.sector_id == sector) sequence.push_back(&m);
  return sequence;
}

/// A corner centred on [start, start + length) of the road, widened for the speed driven through it.
CornerShape cornerShape(const ProgrammeSector& sector, double start_m, double turn_sign, const CellTrace& trace,
                        const ProgrammeDriveParams& params, bool* widened) {
  const double angle = sector.angle_deg * kPi / 180.0, centre = start_m + 0.5 * sector.length_m;
  double radius = sector.radius_m, transition = 0.0, half = 0.5 * sector.length_m;
  // Twice: the speed on the widened corner may be higher than on the sector itself.
  for (int pass = 0; pass < 2; ++pass) {
    const double v_max = trace.maxSpeed(centre - half, centre + half);
    radius = std::max(sector.radius_m, v_max * v_max / params.max_lateral_accel_mps2);
    transition = std::min(v_max * params.steer_transition_s, radius * angle);
    half = 0.5 * (radius * angle + transition);
  }
  *widened = radius > sector.radius_m;
  return {centre - half, transition, radius * angle - transition, turn_sign / radius};
}

/// The route as segments of linear curvature between every break point of the corners (their sum).
Route routeOf(const std::vector<CornerShape>& corners, double length_m) {
  std::vector<double> breaks = {0.0, length_m};
  for (const CornerShape& c : corners) {
    for (double s : {c.start_m, c.start_m + c.transition_m, c.start_m + c.transition_m + c.arc_m, c.end_m()})
      if (s > 0.0 && s < length_m) breaks.push_back(s);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(
      std::unique(breaks.begin(), breaks.end(), [](double a, double b) { return b - a < kDistanceRounding_m; }),
      breaks.end());
  auto curvature = [&corners](double s) {
    double kappa = 0.0;
    for (const CornerShape& c : corners)
      if (s > c.start_m && s < c.end_m()) kappa += c.curvature(s);
    return kappa;
  };
  std::vector<RouteSegment> segments;
  segments.reserve(breaks.size());
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double s0 = breaks[k], s1 = breaks[k + 1];
    // Evaluated just inside the segment, so that a clothoid's end value is the segment's own.
    const double eps = 1e-9 * std::max(1.0, s1);
    segments.push_back({s0, s1 - s0, curvature(s0 + eps), curvature(s1 - eps), -1});
  }
  return Route(std::move(segments), {});
}

}  // namespace

double Track::lapLength_m() const {
  double length = 0.0;
  for (const ProgrammeSector& s : sectors) length += s.length_m;
  return length;
}

const Track* DrivingProgramme::track(const std::string& name) const {
  for (const Track& t : tracks)
    if (t.name == name) return &t;
  return nullptr;
}

const ProgrammeSection* DrivingProgramme::section(const std::string& id) const {
  for (const ProgrammeSection& s : sections)
    if (s.id == id) return &s;
  return nullptr;
}

bool DrivingProgramme::validate(std::string* error) const {
  auto fail = [error](const std::string& where, const std::string& what) {
    if (error) *error = where + ": " + what;
    return false;
  };
  for (const Track& t : tracks) {
    if (t.sectors.empty()) return fail(t.name, "no sectors");
    for (const ProgrammeSector& s : t.sectors) {
      const std::string where = t.name + " sector " + s.id;
      if (!(s.length_m > 0.0) || !std::isfinite(s.length_m)) return fail(where, "length must be > 0");
      if (!std::isfinite(s.grade_percent) || std::fabs(s.grade_percent) >= 100.0)
        return fail(where, "longitudinal slope must be within +-100 %");
      if (!finiteNonNegative(s.crossfall_percent) || s.crossfall_percent >= 100.0)
        return fail(where, "lateral slope must be in [0, 100) %");
      if (!finiteNonNegative(s.radius_m) || !finiteNonNegative(s.angle_deg))
        return fail(where, "corner radius and angle must be >= 0");
      if ((s.radius_m > 0.0) != (s.angle_deg > 0.0))
        return fail(where, "a corner needs both a radius and an angle (a straight neither)");
      if (s.radius_m > 0.0 && s.turn != 1 && s.turn != -1) return fail(where, "a corner needs a turn direction");
      if (s.radius_m > 0.0 && std::fabs(s.radius_m * s.angle_deg * kPi / 180.0 - s.length_m) > 0.02 * s.length_m)
        return fail(where, "radius x angle differs from the length by more than 2 %");
    }
  }
  for (const ProgrammeSection& section : sections) {
    const Track* t = track(section.track);
    if (t == nullptr) return fail(section.id, "unknown track '" + section.track + "'");
    if (section.laps < 1) return fail(section.id, "laps must be >= 1");
    for (const ProgrammeManoeuvre& m : section.manoeuvres) {
      const std::string where = section.id + " sector " + m.sector_id;
      if (std::none_of(t->sectors.begin(), t->sectors.end(),
                       [&m](const ProgrammeSector& s) { return s.id == m.sector_id; }))
        return fail(where, "not a sector of " + section.track);
      if (m.repeats < 1) return fail(where, "repeats must be >= 1");
      if (!finiteNonNegative(m.start_speed_mps) || !finiteNonNegative(m.end_speed_mps))
        return fail(where, "speeds must be >= 0");
      if (m.kind == ProgrammeManoeuvreKind::kAcceleration && !(m.accel_mps2 > 0.0 && std::isfinite(m.accel_mps2)))
        return fail(where, "an acceleration needs an acceleration constant > 0");
      if (m.kind == ProgrammeManoeuvreKind::kDeceleration && !(m.decel_mps2 > 0.0 && std::isfinite(m.decel_mps2)))
        return fail(where, "a deceleration needs a deceleration constant > 0");
    }
    for (const ProgrammeSector& s : t->sectors) {
      const auto sequence = sectorSequence(section, s.id);
      for (const ProgrammeManoeuvre* m : sequence)
        if (m->repeats != sequence.front()->repeats)
          return fail(section.id + " sector " + s.id, "its manoeuvres have different repeat counts");
    }
  }
  return true;
}

bool ProgrammeDriveParams::validate(std::string* error) const {
  if (!(max_lateral_accel_mps2 > 0.0) || !std::isfinite(max_lateral_accel_mps2))
    return failValidation(error, "max_lateral_accel_mps2", max_lateral_accel_mps2, "finite and > 0 [m/s^2]");
  if (!finiteNonNegative(steer_transition_s))
    return failValidation(error, "steer_transition_s", steer_transition_s, "finite and >= 0 [s]");
  if (!finiteNonNegative(smoothing_s)) return failValidation(error, "smoothing_s", smoothing_s, "finite and >= 0 [s]");
  if (!(corner_brake_mps2 > 0.0) || !std::isfinite(corner_brake_mps2))
    return failValidation(error, "corner_brake_mps2", corner_brake_mps2, "finite and > 0 [m/s^2]");
  if (!(corner_accel_mps2 > 0.0) || !std::isfinite(corner_accel_mps2))
    return failValidation(error, "corner_accel_mps2", corner_accel_mps2, "finite and > 0 [m/s^2]");
  return true;
}

VehicleMotion ProgrammeMotion::at(double t_s) const {
  VehicleMotion motion = trace_.at(t_s);
  if (road_.empty()) return motion;
  const double s = trace_.position(t_s);
  auto it = std::upper_bound(road_.begin(), road_.end(), s,
                             [](double value, const RoadPiece& piece) { return value < piece.s_start_m; });
  const RoadPiece& piece = it == road_.begin() ? road_.front() : *(it - 1);
  motion.grade_rad = piece.grade_rad;
  motion.bank_rad = piece.bank_rad;
  return motion;
}

ProgrammeDrive buildProgrammeDrive(const DrivingProgramme& programme, const ProgrammeSection& section_in,
                                   const ProgrammeDriveParams& params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("programme drive: " + error);
  DrivingProgramme one{programme.tracks, {section_in}};
  if (!one.validate(&error)) throw std::invalid_argument("driving programme: " + error);
  const ProgrammeSection* section = &section_in;
  if (section->manoeuvres.empty())
    throw std::invalid_argument("driving programme: " + section->id + " has no manoeuvres");
  const Track& track = *programme.track(section->track);
  const double lap_m = track.lapLength_m();

  CellTrace trace(section->manoeuvres.front().start_speed_mps);
  double debt_m = 0.0;
  for (int lap = 0; lap < section->laps; ++lap) {
    for (const ProgrammeSector& sector : track.sectors) {
      const auto sequence = sectorSequence(*section, sector.id);
      const int repeats = sequence.empty() ? 1 : sequence.front()->repeats;
      for (int r = 0; r < repeats; ++r) drivePass(sequence, sector.length_m / repeats, &debt_m, &trace);
    }
  }

  if (params.slow_for_corners) {
    std::vector<std::array<double, 3>> caps;
    for (int lap = 0; lap < section->laps; ++lap) {
      double start_m = lap * lap_m;
      for (const ProgrammeSector& sector : track.sectors) {
        if (sector.radius_m > 0.0) {
          const double v_corner = std::sqrt(params.max_lateral_accel_mps2 * sector.radius_m);
          const double run_in_m = 0.5 * v_corner * params.steer_transition_s;
          caps.push_back({start_m - run_in_m - kCapGrid_m, start_m + sector.length_m + run_in_m + kCapGrid_m, v_corner});
        }
        start_m += sector.length_m;
      }
    }
    trace = trace.capped(caps, params.corner_brake_mps2, params.corner_accel_mps2, kCapGrid_m);
  }
  const double mirror = params.mirror ? -1.0 : 1.0;
  std::vector<CornerShape> corners;
  std::vector<RoadPiece> road;
  int widened = 0;
  for (int lap = 0; lap < section->laps; ++lap) {
    double start_m = lap * lap_m;
    for (const ProgrammeSector& sector : track.sectors) {
      const double slope = std::atan(sector.crossfall_percent / 100.0);
      const bool corner = sector.radius_m > 0.0;
      // A corner's bank falls towards its inside; a straight's crossfall to the right of travel.
      road.push_back({start_m, start_m + sector.length_m, std::atan(sector.grade_percent / 100.0),
                      corner ? mirror * sector.turn * slope : -slope});
      if (corner) {
        bool was_widened = false;
        corners.push_back(cornerShape(sector, start_m, mirror * sector.turn, trace, params, &was_widened));
        if (lap == 0 && was_widened) ++widened;
      }
      start_m += sector.length_m;
    }
  }
  const double length_m = std::max(trace.distance(), section->laps * lap_m);
  ProgrammeDrive drive{ProgrammeMotion(SpeedTrace(section->manoeuvres.front().start_speed_mps, trace.cells(),
                                                  trace.duration(), params.smoothing_s, routeOf(corners, length_m)),
                                       std::move(road)),
                       lap_m, std::max(0.0, trace.distance() - section->laps * lap_m), widened, 0.0};
  for (double t = 0.0; t <= drive.motion.duration_s(); t += kStatsStep_s) {
    const VehicleMotion m = drive.motion.at(t);
    drive.max_lateral_accel_mps2 =
        std::max(drive.max_lateral_accel_mps2, std::fabs(m.speed_mps * m.speed_mps * m.path_curvature_per_m));
  }
  return drive;
}

}  // namespace tread_wear
