#include "tread_wear/vehicle/manoeuvre.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool saneAccel(double v) { return positive(v) && v <= kMaxManoeuvreAccel_mps2; }
static_assert(kMaxManoeuvreAccel_mps2 == 8.0, "the constraint text below names the bound");
constexpr const char* kSaneAccel = "finite, > 0 and <= 8 (0.8 g)";

/// A route of one segment of constant curvature, long enough for the distance driven.
Route constantCurvatureRoute(double length_m, double curvature_per_m) {
  return Route({RouteSegment{0.0, length_m, curvature_per_m, curvature_per_m, -1}}, {});
}

}  // namespace

const char* manoeuvreName(Manoeuvre manoeuvre) {
  switch (manoeuvre) {
    case Manoeuvre::kProfile: return "profile";
    case Manoeuvre::kCruise: return "cruise";
    case Manoeuvre::kCircle: return "circle";
    case Manoeuvre::kAccelCycles: return "accel";
  }
  return "unknown";
}

bool parseManoeuvre(const std::string& name, Manoeuvre* manoeuvre) {
  for (Manoeuvre m : {Manoeuvre::kProfile, Manoeuvre::kCruise, Manoeuvre::kCircle, Manoeuvre::kAccelCycles}) {
    if (name == manoeuvreName(m)) {
      *manoeuvre = m;
      return true;
    }
  }
  return false;
}

bool ManoeuvreParams::validate(std::string* error) const {
  if (!positive(duration_s)) return failValidation(error, "duration_s", duration_s, "finite and > 0");
  switch (kind) {
    case Manoeuvre::kProfile: return true;
    case Manoeuvre::kCircle:
      if (!saneAccel(lateral_accel_mps2))
        return failValidation(error, "lateral_accel_mps2", lateral_accel_mps2, kSaneAccel);
      [[fallthrough]];
    case Manoeuvre::kCruise:
      if (!positive(speed_mps)) return failValidation(error, "speed_mps", speed_mps, "finite and > 0");
      return true;
    case Manoeuvre::kAccelCycles:
      if (!(std::isfinite(low_speed_mps) && low_speed_mps >= 0.0))
        return failValidation(error, "low_speed_mps", low_speed_mps, "finite and >= 0");
      if (!(std::isfinite(high_speed_mps) && high_speed_mps > low_speed_mps))
        return failValidation(error, "high_speed_mps", high_speed_mps, "finite and > low_speed_mps");
      if (!saneAccel(accel_mps2)) return failValidation(error, "accel_mps2", accel_mps2, kSaneAccel);
      if (!saneAccel(decel_mps2)) return failValidation(error, "decel_mps2", decel_mps2, kSaneAccel);
      return true;
  }
  return true;
}

SpeedTrace buildManoeuvre(const ManoeuvreParams& params) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid manoeuvre: " + error);
  const double duration = params.duration_s;
  switch (params.kind) {
    case Manoeuvre::kProfile: break;
    case Manoeuvre::kCruise: {
      const double length = params.speed_mps * duration;
      return SpeedTrace(params.speed_mps, {{duration, 0.0}}, duration, 0.0, constantCurvatureRoute(length, 0.0));
    }
    case Manoeuvre::kCircle: {
      // One second of circle beyond the last sample, so that the last sample is still on it (the route's
      // curvature is 0 past its end).
      const double length = params.speed_mps * (duration + 1.0);
      const double curvature = (params.turn_right ? -1.0 : 1.0) / params.circleRadius_m();
      return SpeedTrace(params.speed_mps, {{duration, 0.0}}, duration, 0.0, constantCurvatureRoute(length, curvature));
    }
    case Manoeuvre::kAccelCycles: {
      const double dv = params.high_speed_mps - params.low_speed_mps;
      // Cells up to half a smoothing window past T, so that the average at the last sample sees the cycle too.
      const double cells_end = duration + kAccelCycleSmoothing_s;
      // Half a window at v_low first, so that the first sample is steady cruise at v_low (a_x = 0) and a_x then
      // rises to a within the window.
      std::vector<SpeedCell> cells = {{kAccelCycleSmoothing_s / 2.0, 0.0}};
      double t = cells.front().duration_s;
      for (bool accelerating = true; t < cells_end; accelerating = !accelerating) {
        const SpeedCell cell = accelerating ? SpeedCell{dv / params.accel_mps2, params.accel_mps2}
                                            : SpeedCell{dv / params.decel_mps2, -params.decel_mps2};
        cells.push_back(cell);
        t += cell.duration_s;
      }
      double distance = 0.0, v = params.low_speed_mps;
      for (const SpeedCell& c : cells) {
        distance += c.duration_s * (v + c.accel_mps2 * c.duration_s / 2.0);
        v += c.accel_mps2 * c.duration_s;
      }
      return SpeedTrace(params.low_speed_mps, cells, duration, kAccelCycleSmoothing_s,
                        constantCurvatureRoute(distance, 0.0));
    }
  }
  throw std::invalid_argument("invalid manoeuvre: kind profile is the profile's drive, not a manoeuvre");
}

}  // namespace tread_wear
