#include "tread_wear/model/adhesion_wear.h"

#include <array>
#include <cmath>

namespace tread_wear {

AdhesionWear::AdhesionWear(const TireParams& params) : params_(params) {}

AdhesionWearResult AdhesionWear::evaluate(const OperatingPoint& op, const ContactPatch& patch,
                                          const TipKinematics& kinematics, double rolling_speed) const {
  AdhesionWearResult result;
  if (off() || !(rolling_speed > 0.0)) return result;
  const double a = patch.halfLength(), b = patch.halfWidth();
  const double r0 = params_.material.rolling_radius_m;
  // Loaded and effective rolling radius of the radially compressed carcass (file comment).
  const double r_l = r0 - a * a / (2.0 * r0);
  const double r_e = r_l + a * a / (3.0 * r_l);
  const double fr_scale = 1.0 / (3.0 * r_l * r_e);
  result.free_rolling_shear_m = 2.0 * a * a * a * fr_scale / (3.0 * std::sqrt(3.0));  // at x = a / sqrt(3)
  const double k_x = params_.tread.longitudinalStiffness(op.load_n), k_y = params_.tread.lateralStiffness(op.load_n);
  const double omega = kinematics.omega_rad_per_s;
  const double sy = kinematics.v_ry0_mps / rolling_speed, om = omega / rolling_speed;

  // The static limit sat(p) mu_0 p separates in x and y where p >= p_0, as p does (Eqs 8, 11): p^(1-q) p_ref^q.
  const FrictionParams& f = params_.friction;
  const double p_floor_limit = f.mu_0 * std::pow(f.p_0_pa / f.p_ref_pa, -f.q);  // limit / p below p_0
  const double p_above_scale = f.mu_0 * std::pow(f.p_ref_pa, f.q);
  constexpr int nx = AdhesionGrid::kNx, ny = 2 * AdhesionGrid::kNy;
  const double dx = 2.0 * a / nx, dy = 2.0 * b / ny;
  std::array<double, nx + 1> px{}, px_pow{};
  for (int i = 0; i <= nx; ++i) {
    px[i] = patch.lineLoad(a - i * dx) / (2.0 * b);
    px_pow[i] = std::pow(px[i], 1.0 - f.q);
  }
  // Deflection energy e = (k_x delta_x^2 + k_y delta_y^2) / 2 and the static-limit margin at x on strip y.
  auto energyAndMargin = [&](double x, double sx, double p, double p_pow_y, double* e) {
    const double lead = a - x;
    const double delta_x = sx * lead + x * (a * a - x * x) * fr_scale;
    const double delta_y = sy * lead - 0.5 * om * (a * a - x * x);
    *e = 0.5 * (k_x * delta_x * delta_x + k_y * delta_y * delta_y);
    const double limit = p >= f.p_0_pa ? p_above_scale * p_pow_y : p_floor_limit * p;
    return limit - std::hypot(k_x * delta_x, k_y * delta_y);
  };

  // Per strip, the shear work is the total variation of e along the adhesion zone (|tau . d delta| = |de|): node
  // differences are exact where e is monotone between nodes, and the release point is interpolated in the margin.
  double work = 0.0;
  for (int j = 0; j < ny; ++j) {
    const double eta = -1.0 + (j + 0.5) * 2.0 / ny, y = b * eta;
    const double gy = patch.shapeY()(eta), gy_pow = std::pow(gy, 1.0 - f.q);
    const double sx = (kinematics.v_rx0_mps + omega * y) / rolling_speed;
    bool adhered = false;
    double e_prev = 0.0, margin_prev = 0.0, strip = 0.0;
    for (int i = 0; i <= nx; ++i) {
      const double x = a - i * dx;
      double e = 0.0;
      const double margin = energyAndMargin(x, sx, px[i] * gy, px_pow[i] * gy_pow, &e);
      if (margin >= 0.0) {
        if (adhered) strip += std::fabs(e - e_prev);
        adhered = true;  // a leading band that slid is captured here with the deflection it has
        e_prev = e;
      } else if (adhered) {
        // Released between the previous node and this one: the brush's sliding wear from there on.
        const double xs = x + dx * (-margin) / (margin_prev - margin);
        const double t = (a - xs) / dx - (i - 1);  // position of xs within the interval, in [0, 1]
        double e_s = 0.0;
        energyAndMargin(xs, sx, (px[i - 1] + t * (px[i] - px[i - 1])) * gy, 0.0, &e_s);
        strip += std::fabs(e_s - e_prev);
        break;
      }
      margin_prev = margin;
    }
    work += strip * dy;
  }
  // Work per distance rolled; the tread crosses the patch at V_r, the wheel centre moves at V.
  result.work_j_per_m = work * rolling_speed / op.speed_mps;
  result.wear_kg_per_m =
      params_.wear.adhesion_kg_per_j * params_.wear.temperatureFactor(op.tread_temperature_c) * result.work_j_per_m;
  return result;
}

}  // namespace tread_wear
