#include "tread_wear/core/brush_wear_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tread_wear/core/units.h"

namespace tread_wear {

bool GridSpec::validate(std::string* error) const {
  if (n_x_steps < 4) {
    if (error) *error = "grid.n_x_steps = " + std::to_string(n_x_steps) + ": must be >= 4";
    return false;
  }
  if (n_strips < 1) {
    if (error) *error = "grid.n_strips = " + std::to_string(n_strips) + ": must be >= 1";
    return false;
  }
  if (!(edge_grading >= 0.0 && edge_grading < 1.0)) {
    if (error) *error = "grid.edge_grading = " + std::to_string(edge_grading) + ": must be in [0, 1)";
    return false;
  }
  return true;
}

bool BrushOptions::validate(std::string* error) const {
  if (!grid.validate(error)) return false;
  if (turn_slip_iterations < 1) {
    if (error) *error = "turn_slip_iterations = " + std::to_string(turn_slip_iterations) + ": must be >= 1";
    return false;
  }
  if (!(creep_floor_mps > 0.0)) {
    if (error) *error = "creep_floor_mps = " + std::to_string(creep_floor_mps) + ": must be > 0";
    return false;
  }
  return true;
}

void PatchFields::resize(int nx, int ny) {
  n_x_nodes = nx;
  n_strips = ny;
  const size_t n = static_cast<size_t>(nx) * static_cast<size_t>(ny);
  x_m.resize(nx);
  y_m.resize(ny);
  for (auto* v : {&pressure_pa, &tau_x_pa, &tau_y_pa, &v_sx_mps, &v_sy_mps, &delta_x_m, &delta_y_m, &wear_kg_per_m3})
    v->resize(n);
  state.resize(n);
}

BrushWearModel::BrushWearModel(const TireParams& params, const BrushOptions& options)
    : params_(params), options_(options), friction_(params.friction) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid tire parameters: " + error);
  if (!options.validate(&error)) throw std::invalid_argument("invalid brush options: " + error);

  const int n = options.grid.n_x_steps;
  const double beta = options.grid.edge_grading;
  s_.resize(n + 1);
  for (int i = 0; i <= n; ++i) {
    const double u = 1.0 - 2.0 * i / n;  // uniform, leading edge first
    s_[i] = (1.0 - beta) * u + beta * std::sin(0.5 * units::kPi * u);
  }
  s_.front() = 1.0;
  s_.back() = -1.0;
  wx_.assign(n + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    const double ds = s_[i] - s_[i + 1];
    wx_[i] += 0.5 * ds;
    wx_[i + 1] += 0.5 * ds;
  }
  const PressureShape gx(params.footprint.n_x, params.footprint.lambda_x, 0.0);
  gx_even_.resize(n + 1);
  for (int i = 0; i <= n; ++i) gx_even_[i] = gx.even(s_[i]);

  const int ny = options.grid.n_strips;
  eta_.resize(ny);
  wy_.resize(ny);
  gy_.resize(ny);
  const PressureShape gy(params.footprint.n_y, params.footprint.lambda_y, params.footprint.y_e_m / params.footprint.b_m);
  auto map = [](double t) { return std::sin(0.5 * units::kPi * t); };  // clusters strips at the shoulders
  for (int j = 0; j < ny; ++j) {
    const double t0 = -1.0 + 2.0 * j / ny, t1 = -1.0 + 2.0 * (j + 1) / ny;
    eta_[j] = map(0.5 * (t0 + t1));
    wy_[j] = map(t1) - map(t0);
    gy_[j] = gy(eta_[j]);
  }
}

namespace {

/// Solves the slide branch of the return mapping. With D = diag(D_x, D_y) and trial stress t, the
/// sliding speed s = |v_s| is the root of F(s) = sum_i t_i^2 / (D_i s + mu(s) p)^2 - 1, monotone
/// decreasing while D_i + p dmu/ds > 0 (always true for the element inertia m/dt at usable steps).
/// Newton in z = ln s, safeguarded by bisection on the bracket [s_floor, |t|/min D].
struct SlideSolution {
  double s = 0.0;  ///< |v_s| [m/s]
  int iterations = 0;
};

SlideSolution solveSlide(const SavkoorFriction& fr, double sat, double p, double tx, double ty, double dx, double dy,
                         double s_floor) {
  const double t2x = tx * tx, t2y = ty * ty;
  auto F = [&](double s, double* dF_dz) {
    const double mu = sat * fr.savkoor(s);
    const double dmu = sat * fr.savkoorDerivative(s);
    const double gx = dx * s + mu * p, gy = dy * s + mu * p;
    const double f = t2x / (gx * gx) + t2y / (gy * gy) - 1.0;
    if (dF_dz) *dF_dz = -2.0 * s * (t2x * (dx + dmu * p) / (gx * gx * gx) + t2y * (dy + dmu * p) / (gy * gy * gy));
    return f;
  };
  SlideSolution sol;
  const double s_hi0 = std::sqrt(t2x + t2y) / std::min(dx, dy);
  if (F(s_floor, nullptr) <= 0.0) return sol;  // creep: v_s -> 0+ at the static limit
  double z_lo = std::log(s_floor), z_hi = std::log(s_hi0);
  // Start from the viscous estimate, which is the answer when friction is nearly constant.
  const double mu0p = sat * fr.params().mu_0 * p;
  double s = std::max(s_floor, (std::sqrt(t2x + t2y) - mu0p) / std::max(dx, dy));
  double z = std::min(std::log(s), z_hi);
  for (int it = 1; it <= 80; ++it) {
    double dfdz = 0.0;
    const double f = F(std::exp(z), &dfdz);
    sol.iterations = it;
    if (f > 0.0) z_lo = z; else z_hi = z;
    if (std::fabs(f) < 1e-14 || z_hi - z_lo < 1e-13) break;
    double z_new = (dfdz < 0.0) ? z - f / dfdz : 0.5 * (z_lo + z_hi);
    if (!(z_new > z_lo && z_new < z_hi)) z_new = 0.5 * (z_lo + z_hi);
    if (std::fabs(z_new - z) < 1e-13) {
      z = z_new;
      break;
    }
    z = z_new;
  }
  sol.s = std::exp(z);
  return sol;
}

}  // namespace

void BrushWearModel::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) const {
  const FootprintParams& fp = params_.footprint;
  const TreadParams& tp = params_.tread;
  const WearLawParams& wl = params_.wear;
  const double Fz = op.load_n;
  const double a = fp.halfLength(Fz);
  const double b = fp.b_m;
  const double Bx = PressureShape(fp.n_x, fp.lambda_x, fp.x_e_m / a).B();
  const double ky = tp.k_y0_pa_per_m + tp.k_y1_pa_per_m_n * Fz;
  const double kx = tp.phi * ky;
  const double cx = tp.c_x_pa_s_per_m, cy = tp.c_y_pa_s_per_m, m = tp.m_kg_per_m2;
  const double V = op.speed_mps;
  const double Vx = op.longitudinalSpeed();
  const double Vr = op.rollingSpeed();
  const double curvature =
      options_.orientation == TurnSlipOrientation::kFlipped ? -op.path_curvature_per_m : op.path_curvature_per_m;
  const double Omega = V * curvature;  // yaw rate over the road [rad/s]
  const double vrx0 = op.slip_ratio * Vx;
  const double vry0 = -V * std::sin(op.slip_angle_rad);
  const double w3 = wl.w3_kg_per_s_m2 * wl.temperatureFactor(op.tread_temperature_c);
  const double v_m = params_.friction.v_m_mps;
  const double p_scale = Fz / (2.0 * a) / (2.0 * b);  // p = p_scale g_x g_y
  const int n = static_cast<int>(s_.size()) - 1;
  const int ny = static_cast<int>(eta_.size());

  double fx = 0.0, fy = 0.0, mz = 0.0, wear_t = 0.0, stick_area = 0.0, exact_area = 0.0;
  int max_iterations = 0;
  if (fields) {
    for (int i = 0; i <= n; ++i) fields->x_m[i] = a * s_[i];
    for (int j = 0; j < ny; ++j) fields->y_m[j] = b * eta_[j];
  }

  for (int j = 0; j < ny; ++j) {
    const double y = b * eta_[j];
    const double gy = gy_[j];
    // Element state at the current node n and the previous node n-1 (for BDF2).
    double dlx = 0.0, dly = 0.0, ux = 0.0, uy = 0.0;
    double dlx_prev = 0.0, dly_prev = 0.0, ux_prev = 0.0, uy_prev = 0.0;
    double h_prev = 0.0;
    auto vr = [&](double x, double ddx, double ddy, double* rx, double* ry) {
      *rx = vrx0 + Omega * (y + ddy);
      *ry = vry0 - Omega * (x + ddx);
    };
    if (options_.enter_at_road_velocity) vr(a, 0.0, 0.0, &ux, &uy);

    auto record = [&](int i, double p, double tx, double ty, double vsx, double vsy, double s, bool stuck) {
      const double w = wx_[i] * a * wy_[j] * b;  // area weight [m^2]
      const double x = a * s_[i];
      fx += tx * w;
      fy += ty * w;
      mz += (x * ty - y * tx) * w;
      const double tau = std::sqrt(tx * tx + ty * ty);
      double wt = wl.w4_kg_per_s_m2;  // Eq 19 numerator, per time [kg/(s m^2)]
      if (s > 0.0 && tau > 0.0) wt += w3 * std::pow(tau / units::kMegapascal, wl.w1) * std::pow(s, wl.w2);
      wear_t += wt * w;
      if (s <= v_m) stick_area += w;
      if (stuck) exact_area += w;
      if (fields) {
        const int k = fields->index(i, j);
        fields->pressure_pa[k] = p;
        fields->tau_x_pa[k] = tx;
        fields->tau_y_pa[k] = ty;
        fields->v_sx_mps[k] = vsx;
        fields->v_sy_mps[k] = vsy;
        fields->delta_x_m[k] = dlx;
        fields->delta_y_m[k] = dly;
        fields->wear_kg_per_m3[k] = wt / V;
        fields->state[k] = stuck ? 0 : (s <= v_m ? 1 : 2);
      }
    };

    {  // Leading edge: p = 0, no friction; the element slips at u - v_r.
      double rx, ry;
      vr(a, 0.0, 0.0, &rx, &ry);
      const double vsx = ux - rx, vsy = uy - ry;
      const double s = std::sqrt(vsx * vsx + vsy * vsy);
      record(0, 0.0, 0.0, 0.0, vsx, vsy, s, s == 0.0);
    }

    for (int i = 0; i < n; ++i) {
      const double h = a * (s_[i] - s_[i + 1]) / Vr;  // time step [s]
      double a1 = 1.0, a2 = 0.0, beta = 1.0;         // BDF1 on the first step, then variable-step BDF2
      if (i > 0) {
        const double w = h / h_prev;
        a1 = (1.0 + w) * (1.0 + w) / (1.0 + 2.0 * w);
        a2 = -w * w / (1.0 + 2.0 * w);
        beta = (1.0 + w) / (1.0 + 2.0 * w);
      }
      const double g = beta * h;
      const double dhx = a1 * dlx + a2 * dlx_prev, dhy = a1 * dly + a2 * dly_prev;
      const double uhx = a1 * ux + a2 * ux_prev, uhy = a1 * uy + a2 * uy_prev;
      const double Dx = m / g + cx + kx * g, Dy = m / g + cy + ky * g;
      const double bx = m * uhx / g - kx * dhx, by = m * uhy / g - ky * dhy;
      const double x = a * s_[i + 1];
      const double gxv = gx_even_[i + 1] * (1.0 - Bx * s_[i + 1]);
      const double p = std::max(0.0, p_scale * gxv * gy);
      const double sat = friction_.saturation(p);
      const double tau_static = sat * params_.friction.mu_0 * p;

      double ndx = dhx + g * ux, ndy = dhy + g * uy;  // predictor for the Omega delta coupling
      double tx = 0.0, ty = 0.0, nux = 0.0, nuy = 0.0, vsx = 0.0, vsy = 0.0, s = 0.0;
      bool stuck = false;
      for (int pass = 0; pass < options_.turn_slip_iterations; ++pass) {
        double rx, ry;
        vr(x, ndx, ndy, &rx, &ry);
        const double ttx = Dx * rx - bx, tty = Dy * ry - by;  // stress needed to stick
        if (ttx * ttx + tty * tty <= tau_static * tau_static) {
          stuck = true;
          tx = ttx;
          ty = tty;
          s = vsx = vsy = 0.0;
        } else {
          stuck = false;
          const SlideSolution sol = solveSlide(friction_, sat, p, ttx, tty, Dx, Dy, options_.creep_floor_mps);
          max_iterations = std::max(max_iterations, sol.iterations);
          s = sol.s;
          const double mup = sat * friction_.savkoor(s) * p;
          const double gxs = Dx * s + mup, gys = Dy * s + mup;
          if (s > 0.0) {
            vsx = -ttx * s / gxs;
            vsy = -tty * s / gys;
            tx = mup * ttx / gxs;
            ty = mup * tty / gys;
          } else {  // creep at the static limit along the trial direction
            const double tt = std::sqrt(ttx * ttx + tty * tty);
            vsx = vsy = 0.0;
            tx = tau_static * ttx / tt;
            ty = tau_static * tty / tt;
          }
        }
        nux = (tx + bx) / Dx;
        nuy = (ty + by) / Dy;
        ndx = dhx + g * nux;
        ndy = dhy + g * nuy;
      }
      dlx_prev = dlx;
      dly_prev = dly;
      ux_prev = ux;
      uy_prev = uy;
      dlx = ndx;
      dly = ndy;
      ux = nux;
      uy = nuy;
      h_prev = h;
      record(i + 1, p, tx, ty, vsx, vsy, s, stuck);
    }
  }

  const double area = 4.0 * a * b;  // sum of the weights equals the area exactly
  result->fx_n = fx;
  result->fy_n = fy;
  result->mz_nm = mz;
  result->wear_rate_kg_per_s = wear_t;
  result->wear_rate_kg_per_m = wear_t / V;
  result->stick_fraction = stick_area / area;
  result->slide_fraction = 1.0 - result->stick_fraction;
  result->exact_stick_fraction = exact_area / area;
  result->half_length_m = a;
  result->half_width_m = b;
  result->max_root_iterations = max_iterations;
}

}  // namespace tread_wear
