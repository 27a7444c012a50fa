#include "tread_wear/core/brush_wear_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/core/units.h"

namespace tread_wear {

bool GridSpec::validate(std::string* error) const {
  if (n_x_steps < 4) {
    if (error) *error = "grid.n_x_steps = " + std::to_string(n_x_steps) + ": must be >= 4";
    return false;
  }
  if (n_strips < 1 || n_strips > kMaxStrips) {
    if (error)
      *error = "grid.n_strips = " + std::to_string(n_strips) + ": must be in [1, " + std::to_string(kMaxStrips) + "]";
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
  if (max_root_iterations < 1) {
    if (error) *error = "max_root_iterations = " + std::to_string(max_root_iterations) + ": must be >= 1";
    return false;
  }
  if (!(root_tolerance > 0.0 && root_tolerance <= 0.1)) {
    if (error) *error = "root_tolerance = " + std::to_string(root_tolerance) + ": must be in (0, 0.1]";
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

namespace {

/// Gauss-Legendre nodes (ascending) and weights on [-1, 1] by Newton iteration on P_n.
void gaussLegendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
  nodes->assign(n, 0.0);
  weights->assign(n, 0.0);
  for (int k = 0; k < (n + 1) / 2; ++k) {
    double x = std::cos(units::kPi * (k + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int l = 2; l <= n; ++l) {
        const double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0;
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-16) break;
    }
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    (*nodes)[k] = -x;
    (*nodes)[n - 1 - k] = x;
    (*weights)[k] = (*weights)[n - 1 - k] = w;
  }
  if (n % 2 == 1) (*nodes)[n / 2] = 0.0;
}

}  // namespace

BrushWearModel::BrushWearModel(const TireParams& params, const BrushOptions& options)
    : params_(params), options_(options), friction_(params.friction) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid tire parameters: " + error);
  if (!options.validate(&error)) throw std::invalid_argument("invalid brush options: " + error);

  const int n = options.grid.n_x_steps;
  const double grading = options.grid.edge_grading;
  s_.resize(n + 1);
  for (int i = 0; i <= n; ++i) {
    const double u = 1.0 - 2.0 * i / n;  // uniform, leading edge first
    s_[i] = (1.0 - grading) * u + grading * std::sin(0.5 * units::kPi * u);
  }
  s_.front() = 1.0;
  s_.back() = -1.0;
  wx_.assign(n + 1, 0.0);
  steps_.resize(n);
  for (int i = 0; i < n; ++i) {
    const double ds = s_[i] - s_[i + 1];
    wx_[i] += 0.5 * ds;
    wx_[i + 1] += 0.5 * ds;
    Step& st = steps_[i];
    st.ds = ds;
    st.a1 = 1.0;  // BDF1 on the first step, then variable-step BDF2 (w = h_i / h_{i-1} = ds_i / ds_{i-1})
    st.a2 = 0.0;
    st.beta = 1.0;
    st.w = 1.0;
    if (i > 0) {
      const double w = ds / (s_[i - 1] - s_[i]);
      st.w = w;
      st.a1 = (1.0 + w) * (1.0 + w) / (1.0 + 2.0 * w);
      st.a2 = -w * w / (1.0 + 2.0 * w);
      st.beta = (1.0 + w) / (1.0 + 2.0 * w);
    }
  }
  const PressureShape gx(params.footprint.n_x, params.footprint.lambda_x, 0.0);
  gx_even_.resize(n + 1);
  for (int i = 0; i <= n; ++i) gx_even_[i] = gx.even(s_[i]);

  const int ny = options.grid.n_strips;
  eta_.resize(ny);
  wy_.resize(ny);
  gy_.resize(ny);
  sat_y_.resize(ny);
  const PressureShape gy(params.footprint.n_y, params.footprint.lambda_y, params.footprint.y_e_m / params.footprint.b_m);
  if (options.grid.lateral_rule == LateralRule::kGaussLegendre) {
    gaussLegendre(ny, &eta_, &wy_);
  } else {
    auto map = [](double t) { return std::sin(0.5 * units::kPi * t); };  // clusters strips at the shoulders
    for (int j = 0; j < ny; ++j) {
      const double t0 = -1.0 + 2.0 * j / ny, t1 = -1.0 + 2.0 * (j + 1) / ny;
      eta_[j] = map(0.5 * (t0 + t1));
      wy_[j] = map(t1) - map(t0);
    }
    if (ny % 2 == 1) eta_[ny / 2] = 0.0;
  }
  for (int j = 0; j < ny; ++j) {
    gy_[j] = gy(eta_[j]);
    sat_y_[j] = gy_[j] > 0.0 ? std::pow(gy_[j], -params.friction.q) : 0.0;
  }
  y_symmetric_ = params.footprint.y_e_m == 0.0;
  for (int j = 0; j < ny && y_symmetric_; ++j)
    y_symmetric_ = eta_[j] == -eta_[ny - 1 - j] && wy_[j] == wy_[ny - 1 - j] && gy_[j] == gy_[ny - 1 - j];
}

namespace {

/// Constants of the Savkoor law in l = ln(|v_s|/v_m): savkoor = mu_0 + dmu exp(-c l^2).
struct SavkoorLog {
  double mu_0, dmu, c, ln_vm;
};

/// Root of the slide branch of the return mapping. With D = diag(D_x, D_y) and trial stress t, the
/// sliding speed s = |v_s| solves F(s) = sum_i t_i^2 / (D_i s + mu(s) p)^2 - 1 = 0, monotone
/// decreasing while D_i + p dmu/ds > 0 (true for the element inertia m/dt at usable steps).
/// Newton in z = ln s, safeguarded by bisection on the bracket [s_floor, |t|/min D].
struct SlideRoot {
  double s = 0.0;    ///< |v_s| [m/s]; 0 = creep at the static limit
  double z = 0.0;    ///< ln|v_s|
  double mup = 0.0;  ///< mu(|v_s|, p) p [Pa]
  int iterations = 0;
};

struct SlideProblem {
  double sat_p;      ///< sat(p) p [Pa]
  double t2x, t2y;   ///< squared trial stress components [Pa^2]
  double dx, dy;     ///< D_x, D_y [Pa s/m]
};

/// F and dF/dz at z; also returns s and mu p there.
inline double slideResidual(const SavkoorLog& sk, const SlideProblem& pr, double z, double* dfdz, double* s_out,
                            double* mup_out, double* s_dmup_out) {
  const double s = std::exp(z);
  const double l = z - sk.ln_vm;
  const double e = sk.dmu * std::exp(-sk.c * l * l);
  const double mup = pr.sat_p * (sk.mu_0 + e);
  const double s_dmup = pr.sat_p * e * (-2.0 * sk.c * l);  // s d(mu p)/ds
  const double igx = 1.0 / (pr.dx * s + mup), igy = 1.0 / (pr.dy * s + mup);
  const double rx = pr.t2x * igx * igx, ry = pr.t2y * igy * igy;
  *dfdz = -2.0 * (rx * (pr.dx * s + s_dmup) * igx + ry * (pr.dy * s + s_dmup) * igy);
  *s_out = s;
  *mup_out = mup;
  *s_dmup_out = s_dmup;
  return rx + ry - 1.0;
}

SlideRoot solveSlide(const SavkoorLog& sk, const SlideProblem& pr, double z_floor, double f_floor_mu, double z_guess,
                     bool have_guess, double tol, int max_iterations) {
  SlideRoot root;
  // Creep test at the floor speed: there D s is negligible against mu p and mu = mu(floor) (constant).
  {
    const double mup = pr.sat_p * f_floor_mu;
    if ((pr.t2x + pr.t2y) <= mup * mup) return root;
  }
  // Bracket [z_lo, z_hi]; the a-priori upper end ln(|t| / min D) is only computed if bisection needs it.
  double z_lo = z_floor, z_hi = std::numeric_limits<double>::infinity();
  auto upperEnd = [&]() {
    if (std::isinf(z_hi)) z_hi = std::log(std::sqrt(pr.t2x + pr.t2y) / std::min(pr.dx, pr.dy));
    return z_hi;
  };
  double z = z_guess;
  if (!have_guess || z_guess < sk.ln_vm) {
    const double r = std::sqrt(pr.t2x + pr.t2y);
    // Closed-form creep root mu(s) p = r with D s neglected, on the rising branch (s < v_m): there it
    // is a better start than the warm start; beyond the peak of mu the warm start is.
    const double e = (r / pr.sat_p - sk.mu_0) / sk.dmu;
    if (e > 0.0 && e < 1.0) {
      z = sk.ln_vm - std::sqrt(-std::log(e) / sk.c);
    } else if (!have_guess) {  // viscous estimate: D s carries what friction at its floor mu_0 p does not
      const double s_visc = std::sqrt(pr.t2x / (pr.dx * pr.dx) + pr.t2y / (pr.dy * pr.dy));
      z = std::log(std::max(s_visc * (1.0 - pr.sat_p * sk.mu_0 / r), 1e-300));
    }
  }
  if (!(z > z_lo && z < z_hi)) z = 0.5 * (z_lo + upperEnd());
  for (int it = 1; it <= max_iterations; ++it) {
    double dfdz, s, mup, s_dmup;
    const double f = slideResidual(sk, pr, z, &dfdz, &s, &mup, &s_dmup);
    root.iterations = it;
    if (f > 0.0) z_lo = z; else z_hi = z;
    // Far from the root F + 1 behaves like a power of s (like s^-2 where D s dominates), so Newton
    // on ln(F + 1) is nearly linear in z there; near the root both forms agree to O(F^2).
    const double step = !(dfdz < 0.0) ? 0.0 : (std::fabs(f) < 0.25 ? -f : -(1.0 + f) * std::log1p(f)) / dfdz;
    if (dfdz < 0.0 && std::fabs(step) < tol) {
      // Quadratic convergence: the remaining error is O(step^2); correct s and mu p to first order.
      root.z = z + step;
      root.s = s * (1.0 + step);
      root.mup = mup + s_dmup * step;
      return root;
    }
    double z_new = z + step;
    if (!(dfdz < 0.0) || !(z_new > z_lo && z_new < z_hi)) z_new = 0.5 * (z_lo + upperEnd());
    if (z_hi - z_lo < tol || it == max_iterations) {
      root.z = z_new;
      root.s = std::exp(z_new);
      const double l = z_new - sk.ln_vm;
      root.mup = pr.sat_p * (sk.mu_0 + sk.dmu * std::exp(-sk.c * l * l));
      return root;
    }
    z = z_new;
  }
  return root;
}

/// State of the element travelling along one strip.
struct ElementState {
  double dlx, dly, ux, uy;          ///< deflection [m] and its rate [m/s] at the current node
  double dlx_p, dly_p, ux_p, uy_p;  ///< the same at the previous node (BDF2)
  double z;                         ///< ln|v_s| at the current node if it slid (warm start)
  double z_p;                       ///< ln|v_s| at the previous node if it slid
  bool sliding;                     ///< the current node slid with |v_s| > 0
  bool sliding_p;                   ///< the previous node slid with |v_s| > 0
};

}  // namespace

void BrushWearModel::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) const {
  const FootprintParams& fp = params_.footprint;
  const TreadParams& tp = params_.tread;
  const WearLawParams& wl = params_.wear;
  const FrictionParams& fr = params_.friction;
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
  const double w1 = wl.w1, w2 = wl.w2, w4 = wl.w4_kg_per_s_m2;
  const double ln_w3_over_mpa_w1 = std::log(w3) - w1 * std::log(units::kMegapascal);
  const double v_m = fr.v_m_mps;
  // ln|v_s| below which w3 (|tau|/1 MPa)^w1 |v_s|^w2 < 1e-9 w4 for any |tau| <= 100 MPa.
  const double z_wear_cut = w4 > 0.0 ? (std::log(1e-9 * w4) - ln_w3_over_mpa_w1 - w1 * std::log(100e6)) / w2
                                     : -std::numeric_limits<double>::infinity();
  const double p_scale = Fz / (2.0 * a) / (2.0 * b);  // p = p_scale g_x g_y
  const double sat_floor = friction_.saturation(fr.p_0_pa);
  const int n = static_cast<int>(s_.size()) - 1;
  const int ny = static_cast<int>(eta_.size());
  // Mirror symmetry in y: v_r does not depend on y without turn slip, and g_y is even.
  const bool mirror = options_.use_symmetry && y_symmetric_ && Omega == 0.0;
  const int n_active = mirror ? (ny + 1) / 2 : ny;
  const int passes = Omega == 0.0 ? 1 : options_.turn_slip_iterations;

  const SavkoorLog sk{fr.mu_0, fr.mu_m - fr.mu_0, fr.h * fr.h / (std::log(10.0) * std::log(10.0)), std::log(v_m)};
  const double z_floor = std::log(options_.creep_floor_mps);
  const double savkoor_floor = friction_.savkoor(options_.creep_floor_mps);
  const double tol = options_.root_tolerance;
  const int max_it = options_.max_root_iterations;

  std::array<ElementState, GridSpec::kMaxStrips> el;
  double strip_weight[GridSpec::kMaxStrips];  // area weight factor of a marched strip (2 for mirrored pairs)
  for (int j = 0; j < n_active; ++j) {
    strip_weight[j] = (mirror && 2 * j + 1 != ny) ? 2.0 : 1.0;
    ElementState& e = el[j];
    e = ElementState{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, false, false};
    if (options_.enter_at_road_velocity) {
      e.ux = vrx0 + Omega * b * eta_[j];
      e.uy = vry0 - Omega * a;
    }
  }

  double fx = 0.0, fy = 0.0, mz = 0.0, wear_t = 0.0, stick_area = 0.0, exact_area = 0.0;
  int max_iterations = 0;
  long total_iterations = 0;
  if (fields) {
    for (int i = 0; i <= n; ++i) fields->x_m[i] = a * s_[i];
    for (int j = 0; j < ny; ++j) fields->y_m[j] = b * eta_[j];
  }

  auto store = [&](int i, int j, double p, double tx, double ty, double vsx, double vsy, double wt, unsigned char st) {
    const ElementState& e = el[j];
    for (int jj : {j, ny - 1 - j}) {
      const int k = fields->index(i, jj);
      fields->pressure_pa[k] = p;
      fields->tau_x_pa[k] = tx;
      fields->tau_y_pa[k] = ty;
      fields->v_sx_mps[k] = vsx;
      fields->v_sy_mps[k] = vsy;
      fields->delta_x_m[k] = e.dlx;
      fields->delta_y_m[k] = e.dly;
      fields->wear_kg_per_m3[k] = wt / V;
      fields->state[k] = st;
      if (!mirror) break;
    }
  };

  {  // Leading edge: p = 0, no friction; the element slips at u - v_r.
    const double w0 = wx_[0] * a * b;
    for (int j = 0; j < n_active; ++j) {
      const ElementState& e = el[j];
      const double y = b * eta_[j];
      const double vsx = e.ux - (vrx0 + Omega * y), vsy = e.uy - (vry0 - Omega * a);
      const double s = std::sqrt(vsx * vsx + vsy * vsy);
      const double w = w0 * wy_[j] * strip_weight[j];
      wear_t += w4 * w;
      if (s <= v_m) stick_area += w;
      if (s == 0.0) exact_area += w;
      if (fields) store(0, j, 0.0, 0.0, 0.0, vsx, vsy, w4, s == 0.0 ? 0 : (s <= v_m ? 1 : 2));
    }
  }

  for (int i = 0; i < n; ++i) {
    const Step& st = steps_[i];
    const double g = st.beta * a * st.ds / Vr;  // beta h [s]
    const double m_over_g = m / g;
    const double Dx = m_over_g + cx + kx * g, Dy = m_over_g + cy + ky * g;
    const double inv_dx = 1.0 / Dx, inv_dy = 1.0 / Dy;
    const double x = a * s_[i + 1];
    const double px = std::max(0.0, p_scale * gx_even_[i + 1] * (1.0 - Bx * s_[i + 1]));
    const double sat_x = px > 0.0 ? std::pow(px / fr.p_ref_pa, -fr.q) : 0.0;
    const double wxa = wx_[i + 1] * a * b;
    double fx_i = 0.0, fy_i = 0.0, mz_y = 0.0, wear_i = 0.0, stick_i = 0.0, exact_i = 0.0;
    for (int j = 0; j < n_active; ++j) {
      ElementState& e = el[j];
      const double y = b * eta_[j];
      const double p = px * gy_[j];
      const double sat = p > fr.p_0_pa ? sat_x * sat_y_[j] : sat_floor;
      const double sat_p = sat * p;
      const double tau_static = fr.mu_0 * sat_p;
      const double dhx = st.a1 * e.dlx + st.a2 * e.dlx_p, dhy = st.a1 * e.dly + st.a2 * e.dly_p;
      const double uhx = st.a1 * e.ux + st.a2 * e.ux_p, uhy = st.a1 * e.uy + st.a2 * e.uy_p;
      const double bx = m_over_g * uhx - kx * dhx, by = m_over_g * uhy - ky * dhy;

      double ndx = dhx + g * e.ux, ndy = dhy + g * e.uy;  // predictor for the Omega delta coupling
      double tx = 0.0, ty = 0.0, nux = 0.0, nuy = 0.0, vsx = 0.0, vsy = 0.0, s = 0.0, mup = 0.0, z = 0.0;
      bool stuck = false;
      for (int pass = 0; pass < passes; ++pass) {
        const double rx = vrx0 + Omega * (y + ndy), ry = vry0 - Omega * (x + ndx);
        const double ttx = Dx * rx - bx, tty = Dy * ry - by;  // stress needed to stick
        const double t2x = ttx * ttx, t2y = tty * tty;
        if (t2x + t2y <= tau_static * tau_static) {
          stuck = true;
          tx = ttx;
          ty = tty;
          s = vsx = vsy = z = 0.0;
        } else {
          stuck = false;
          // Warm start: the previous pass at this node, else ln|v_s| extrapolated along the element path.
          const bool have_guess = s > 0.0 || e.sliding;
          const double guess = s > 0.0 ? z : (e.sliding_p ? e.z + st.w * (e.z - e.z_p) : e.z);
          const SlideRoot root = solveSlide(sk, SlideProblem{sat_p, t2x, t2y, Dx, Dy}, z_floor, savkoor_floor,
                                            guess, have_guess, tol, max_it);
          max_iterations = std::max(max_iterations, root.iterations);
          total_iterations += root.iterations;
          s = root.s;
          if (s > 0.0) {
            mup = root.mup;
            z = root.z;
            const double igx = 1.0 / (Dx * s + mup), igy = 1.0 / (Dy * s + mup);
            vsx = -ttx * s * igx;
            vsy = -tty * s * igy;
            tx = mup * ttx * igx;
            ty = mup * tty * igy;
          } else {  // creep at the static limit along the trial direction
            const double tt = std::sqrt(t2x + t2y);
            vsx = vsy = z = 0.0;
            tx = tau_static * ttx / tt;
            ty = tau_static * tty / tt;
          }
        }
        nux = (tx + bx) * inv_dx;
        nuy = (ty + by) * inv_dy;
        ndx = dhx + g * nux;
        ndy = dhy + g * nuy;
      }
      e.dlx_p = e.dlx;
      e.dly_p = e.dly;
      e.ux_p = e.ux;
      e.uy_p = e.uy;
      e.dlx = ndx;
      e.dly = ndy;
      e.ux = nux;
      e.uy = nuy;
      e.sliding_p = e.sliding;
      e.z_p = e.z;
      e.sliding = s > 0.0;
      e.z = z;

      // Eq 19 per time; at the slide root |tau| = mu p exactly, and ln|v_s| = z is known. Below z_wear_cut
      // the sliding term is under 1e-9 w4 (deep creep) and is skipped.
      const double wt = (s > 0.0 && z > z_wear_cut) ? w4 + std::exp(ln_w3_over_mpa_w1 + w1 * std::log(mup) + w2 * z) : w4;
      const double w = wy_[j] * strip_weight[j];
      fx_i += tx * w;
      fy_i += ty * w;
      if (!mirror) mz_y += y * tx * w;
      wear_i += wt * w;
      if (s <= v_m) stick_i += w;
      if (stuck) exact_i += w;
      if (fields) store(i + 1, j, p, tx, ty, vsx, vsy, wt, stuck ? 0 : (s <= v_m ? 1 : 2));
    }
    fx += fx_i * wxa;
    fy += fy_i * wxa;
    mz += (x * fy_i - mz_y) * wxa;
    wear_t += wear_i * wxa;
    stick_area += stick_i * wxa;
    exact_area += exact_i * wxa;
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
  result->root_iterations = total_iterations;
}

}  // namespace tread_wear
