#include "tread_wear/studies/wear_characteristics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegToRad = M_PI / 180.0;

std::vector<SweepPoint> sweep(const BrushWearModel& model, double load_n, double speed_mps,
                              const CharacteristicsOptions& o) {
  std::vector<SweepPoint> points;
  const int n = static_cast<int>(std::floor(o.max_slip_angle_deg / o.slip_angle_step_deg + 1e-9));
  for (int i = 0; i <= n; ++i) {
    const double alpha_deg = i * o.slip_angle_step_deg;
    OperatingPoint op;
    op.speed_mps = speed_mps;
    op.slip_angle_rad = -alpha_deg * kDegToRad;
    op.path_curvature_per_m = 1.0 / o.track_radius_m;
    op.load_n = load_n;
    WearResult r;
    model.evaluate(op, &r);
    points.push_back({load_n, speed_mps, alpha_deg, r.fy_n, r.wear_rate_kg_per_m, r.stick_fraction});
  }
  return points;
}

std::vector<SweepPoint> pointsOf(const std::vector<SweepPoint>& all, double load_n, double speed_mps) {
  std::vector<SweepPoint> out;
  for (const SweepPoint& p : all)
    if (p.load_n == load_n && p.speed_mps == speed_mps) out.push_back(p);
  return out;
}

}  // namespace

bool CharacteristicsOptions::validate(std::string* error) const {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (loads_n.empty() || speeds_mps.empty() || side_forces_n.empty())
    return fail("loads_n, speeds_mps and side_forces_n must not be empty");
  for (double l : loads_n)
    if (!(l > 0.0)) return fail("loads_n: " + std::to_string(l) + " must be > 0");
  for (double v : speeds_mps)
    if (!(v > 0.0)) return fail("speeds_mps: " + std::to_string(v) + " must be > 0");
  if (!std::is_sorted(loads_n.begin(), loads_n.end()) || !std::is_sorted(speeds_mps.begin(), speeds_mps.end()))
    return fail("loads_n and speeds_mps must be ascending");
  if (!(load_sweep_speed_mps > 0.0)) return fail("load_sweep_speed_mps must be > 0");
  if (!(speed_sweep_load_n > 0.0)) return fail("speed_sweep_load_n must be > 0");
  if (!(slip_angle_step_deg > 0.0)) return fail("slip_angle_step_deg must be > 0");
  if (!(max_slip_angle_deg > slip_angle_step_deg && max_slip_angle_deg < 89.0))
    return fail("max_slip_angle_deg = " + std::to_string(max_slip_angle_deg) + ": must be in (step, 89)");
  if (!(track_radius_m > 0.0)) return fail("track_radius_m must be > 0");
  return brush.validate(error);
}

double wearAtSideForce(const std::vector<SweepPoint>& s, double side_force_n) {
  for (size_t i = 1; i < s.size(); ++i) {
    if (s[i].side_force_n < s[i - 1].side_force_n) break;  // past the grip peak
    if (s[i - 1].side_force_n <= side_force_n && side_force_n <= s[i].side_force_n) {
      const double span = s[i].side_force_n - s[i - 1].side_force_n;
      const double t = span > 0.0 ? (side_force_n - s[i - 1].side_force_n) / span : 0.0;
      return s[i - 1].wear_rate_kg_per_m + t * (s[i].wear_rate_kg_per_m - s[i - 1].wear_rate_kg_per_m);
    }
  }
  return kNaN;
}

GridMinimum refinedMinimum(const std::vector<double>& x, const std::vector<double>& y) {
  GridMinimum m;
  int best = -1;
  for (size_t i = 0; i < y.size(); ++i)
    if (std::isfinite(y[i]) && (best < 0 || y[i] < y[best])) best = static_cast<int>(i);
  if (best < 0) return m;
  m.found = true;
  m.x = x[best];
  m.y = y[best];
  const bool has_left = best > 0 && std::isfinite(y[best - 1]);
  const bool has_right = best + 1 < static_cast<int>(y.size()) && std::isfinite(y[best + 1]);
  if (!has_left || !has_right) {
    m.at_edge = true;
    return m;
  }
  // Parabola through three points (x0, y0), (x1, y1), (x2, y2): vertex by divided differences.
  const double x0 = x[best - 1], x1 = x[best], x2 = x[best + 1];
  const double y0 = y[best - 1], y1 = y[best], y2 = y[best + 1];
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double c2 = (d12 - d01) / (x2 - x0);
  if (c2 > 0.0) {
    const double c1 = d01 - c2 * (x0 + x1);
    const double xv = std::clamp(-c1 / (2.0 * c2), x0, x2);
    m.x = xv;
    m.y = y0 + d01 * (xv - x0) + c2 * (xv - x0) * (xv - x1);
  }
  return m;
}

WearCharacteristics computeWearCharacteristics(const TireParams& params, const CharacteristicsOptions& o) {
  std::string err;
  if (!o.validate(&err)) throw std::invalid_argument("wear characteristics options: " + err);
  const BrushWearModel model(params, o.brush);
  WearCharacteristics wc;
  for (double load : o.loads_n) {
    const auto s = sweep(model, load, o.load_sweep_speed_mps, o);
    wc.load_sweeps.insert(wc.load_sweeps.end(), s.begin(), s.end());
  }
  for (double v : o.speeds_mps) {
    const auto s = sweep(model, o.speed_sweep_load_n, v, o);
    wc.speed_sweeps.insert(wc.speed_sweeps.end(), s.begin(), s.end());
  }
  for (double fy : o.side_forces_n) {
    WearCharacteristics::AtSideForce a;
    a.side_force_n = fy;
    for (double load : o.loads_n)
      a.wear_by_load_kg_per_m.push_back(
          wearAtSideForce(pointsOf(wc.load_sweeps, load, o.load_sweep_speed_mps), fy));
    for (double v : o.speeds_mps)
      a.wear_by_speed_kg_per_m.push_back(wearAtSideForce(pointsOf(wc.speed_sweeps, o.speed_sweep_load_n, v), fy));
    a.optimal_load = refinedMinimum(o.loads_n, a.wear_by_load_kg_per_m);
    const std::vector<double>& w = a.wear_by_speed_kg_per_m;
    for (size_t i = 1; i + 1 < w.size(); ++i)
      if (std::isfinite(w[i - 1]) && std::isfinite(w[i]) && std::isfinite(w[i + 1]) && w[i] < w[i - 1] &&
          w[i] <= w[i + 1]) {
        const std::vector<double> xs(o.speeds_mps.begin() + i - 1, o.speeds_mps.begin() + i + 2);
        const std::vector<double> ys(w.begin() + i - 1, w.begin() + i + 2);
        a.speed_local_minima.push_back(refinedMinimum(xs, ys));
      }
    wc.at_side_force.push_back(a);
  }
  const double v_m = params.friction.v_m_mps;
  for (double v : o.speeds_mps) {
    if (!(v > v_m)) continue;
    const double alpha_deg = std::asin(v_m / v) / kDegToRad;
    OperatingPoint op;
    op.speed_mps = v;
    op.slip_angle_rad = -alpha_deg * kDegToRad;
    op.path_curvature_per_m = 1.0 / o.track_radius_m;
    op.load_n = o.speed_sweep_load_n;
    WearResult r;
    model.evaluate(op, &r);
    wc.vm_condition.push_back({v, alpha_deg, r.fy_n, r.wear_rate_kg_per_m});
  }
  return wc;
}

}  // namespace tread_wear
