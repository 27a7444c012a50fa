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
  // Everything that depends on x alone, per node: the slip lever a - x, the tread-band shear, the turn-slip part of
  // delta_y, the line pressure and its power 1 - q.
  std::array<double, nx + 1> lead{}, d_fr{}, d_turn{}, px{}, px_pow{};
  for (int i = 0; i <= nx; ++i) {
    const double x = a - i * dx;
    lead[i] = a - x;
    d_fr[i] = x * (a * a - x * x) * fr_scale;
    d_turn[i] = -0.5 * om * (a * a - x * x);
    px[i] = patch.lineLoad(x) / (2.0 * b);
    px_pow[i] = std::pow(px[i], 1.0 - f.q);
  }
  // Deflection energy e = (k_x delta_x^2 + k_y delta_y^2) / 2 and the squared margin limit^2 - |k delta|^2 (the sign
  // says stick or slide) at node i of a strip with slip sx, at pressure p and p^(1-q) = p_pow.
  auto node = [&](int i, double sx, double p, double p_pow, double* e) {
    const double tx = k_x * (sx * lead[i] + d_fr[i]), ty = k_y * (sy * lead[i] + d_turn[i]);
    *e = 0.5 * (tx * tx / k_x + ty * ty / k_y);
    const double limit = p >= f.p_0_pa ? p_above_scale * p_pow : p_floor_limit * p;
    return limit * limit - tx * tx - ty * ty;
  };
  // Without turn slip and with a symmetric lateral pressure the strips at -y and y are alike: half of them, twice.
  const bool mirror = omega == 0.0 && params_.footprint.y_e_m == 0.0;
  const int strips = mirror ? ny / 2 : ny;

  // Per strip, the shear work is the total variation of e along the adhesion zone (|tau . d delta| = |de|): node
  // differences are exact where e is monotone between nodes, and the release point is interpolated in the margin.
  double work = 0.0;
  for (int j = 0; j < strips; ++j) {
    const double eta = (mirror ? 0.0 : -1.0) + (j + 0.5) * 2.0 / ny, y = b * eta;
    const double gy = patch.shapeY()(eta), gy_pow = std::pow(gy, 1.0 - f.q);
    const double sx = (kinematics.v_rx0_mps + omega * y) / rolling_speed;
    bool adhered = false;
    double e_prev = 0.0, margin_prev = 0.0, strip = 0.0;
    for (int i = 0; i <= nx; ++i) {
      double e = 0.0;
      const double margin = node(i, sx, px[i] * gy, px_pow[i] * gy_pow, &e);
      if (margin >= 0.0) {
        if (adhered) strip += std::fabs(e - e_prev);
        adhered = true;  // a leading band that slid is captured here with the deflection it has
        e_prev = e;
      } else if (adhered) {
        // Released between the previous node and this one (the brush's sliding wear from there on): e interpolated
        // to the zero of the margin.
        const double t = margin_prev / (margin_prev - margin);
        strip += std::fabs(t * (e - e_prev));
        break;
      }
      margin_prev = margin;
    }
    work += strip * dy * (mirror ? 2.0 : 1.0);
  }
  // Work per distance rolled; the tread crosses the patch at V_r, the wheel centre moves at V.
  result.work_j_per_m = work * rolling_speed / op.speed_mps;
  result.wear_kg_per_m =
      params_.wear.adhesion_kg_per_j * params_.wear.temperatureFactor(op.tread_temperature_c) * result.work_j_per_m;
  return result;
}

}  // namespace tread_wear
