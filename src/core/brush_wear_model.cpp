#include "tread_wear/core/brush_wear_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/core/quadrature.h"
#include "tread_wear/core/units.h"
#include "tread_wear/core/validation.h"

namespace tread_wear {

bool GridSpec::validate(std::string* error) const {
  if (n_x_steps < 4) return failValidation(error, "grid.n_x_steps", n_x_steps, ">= 4");
  if (n_strips < 1 || n_strips > kMaxStrips)
    return failValidation(error, "grid.n_strips", n_strips, "in [1, " + std::to_string(kMaxStrips) + "]");
  if (lateral_rule == LateralRule::kGaussShoulderPanels && (n_strips < 6 || n_strips % 2 != 0))
    return failValidation(error, "grid.n_strips", n_strips, "even and >= 6 with shoulder panels");
  if (!(edge_grading >= 0.0 && edge_grading < 1.0))
    return failValidation(error, "grid.edge_grading", edge_grading, "in [0, 1)");
  return true;
}

bool RefinementOptions::validate(std::string* error) const {
  if (max_level < 0 || max_level > kMaxLevel)
    return failValidation(error, "refinement.max_level", max_level, "in [0, " + std::to_string(kMaxLevel) + "]");
  if (node_budget < 0) return failValidation(error, "refinement.node_budget", node_budget, ">= 0");
  if (!(resolution > 0.0)) return failValidation(error, "refinement.resolution", resolution, "> 0");
  if (!(damping_ratio >= 0.0)) return failValidation(error, "refinement.damping_ratio", damping_ratio, ">= 0");
  return true;
}

bool BrushOptions::validate(std::string* error) const {
  if (!grid.validate(error)) return false;
  if (turn_slip_iterations < 1) return failValidation(error, "turn_slip_iterations", turn_slip_iterations, ">= 1");
  if (!(creep_floor_mps > 0.0)) return failValidation(error, "creep_floor_mps", creep_floor_mps, "> 0");
  if (max_root_iterations < 1) return failValidation(error, "max_root_iterations", max_root_iterations, ">= 1");
  if (!refinement.validate(error)) return false;
  if (!(root_tolerance > 0.0 && root_tolerance <= 0.1))
    return failValidation(error, "root_tolerance", root_tolerance, "in (0, 0.1]");
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

/// Composite Gauss-Legendre rule on [-1, 1] with three panels per half, [0, e1], [e1, e2], [e2, 1],
/// whose ends sit at fixed values of the shape variable t = |y/b|^(2 n_y) of the lateral pressure
/// (Eq 8): t = 0.27 (the pressure is still near its plateau) and t = 0.78 (it has fallen to about half).
/// The shoulder band, a few per cent of the width, carries fast sliding at low pressure and a large
/// share of the wear (~ p^w1 next to the edge); a single Gauss rule puts at most one node there.
/// n is even; the inner panel takes what the two shoulder panels (n/6 each, at least 1) leave.
void shoulderPanels(int n, double n_y, std::vector<double>* nodes, std::vector<double>* weights) {
  const int half = n / 2;
  const int n_shoulder = std::max(1, half / 3);
  const int counts[3] = {half - 2 * n_shoulder, n_shoulder, n_shoulder};
  const double ends[3] = {std::pow(0.27, 0.5 / n_y), std::pow(0.78, 0.5 / n_y), 1.0};
  nodes->assign(n, 0.0);
  weights->assign(n, 0.0);
  std::vector<double> x, w;
  double lo = 0.0;
  int k = half;
  for (int q = 0; q < 3; ++q) {
    gaussLegendre(counts[q], &x, &w);
    const double h = 0.5 * (ends[q] - lo);
    for (int r = 0; r < counts[q]; ++r, ++k) {
      (*nodes)[k] = lo + h * (1.0 + x[r]);
      (*weights)[k] = h * w[r];
      (*nodes)[n - 1 - k] = -(*nodes)[k];
      (*weights)[n - 1 - k] = (*weights)[k];
    }
    lo = ends[q];
  }
}

/// Coefficients of the variable-step BDF2 step y_{i+1} = a1 y_i + a2 y_{i-1} + beta h_i y'_{i+1}.
struct Bdf2 {
  double a1, a2, beta;
};

/// BDF2 coefficients for the step ratio w = h_i / h_{i-1}; w = 0 gives BDF1 (a restart).
Bdf2 bdf2Coefficients(double w) {
  const double d = 1.0 / (1.0 + 2.0 * w);
  return {(1.0 + w) * (1.0 + w) * d, -w * w * d, (1.0 + w) * d};
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
    // BDF1 on the first step, then variable-step BDF2 (w = h_i / h_{i-1} = ds_i / ds_{i-1}).
    const double w = i > 0 ? ds / (s_[i - 1] - s_[i]) : 0.0;
    const Bdf2 c = bdf2Coefficients(w);
    steps_[i] = Step{ds, c.a1, c.a2, c.beta, i > 0 ? w : 1.0};
  }
  gx_ = PressureShape(params.footprint.n_x, params.footprint.lambda_x, 0.0);
  gx_even_.resize(n + 1);
  for (int i = 0; i <= n; ++i) gx_even_[i] = gx_.even(s_[i]);

  const int ny = options.grid.n_strips;
  eta_.resize(ny);
  wy_.resize(ny);
  gy_.resize(ny);
  sat_y_.resize(ny);
  const PressureShape gy(params.footprint.n_y, params.footprint.lambda_y, params.footprint.y_e_m / params.footprint.b_m);
  if (options.grid.lateral_rule == LateralRule::kGaussShoulderPanels) {
    shoulderPanels(ny, params.footprint.n_y, &eta_, &wy_);
  } else if (options.grid.lateral_rule == LateralRule::kGaussLegendre) {
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
  double s_dmup = 0.0;  ///< |v_s| d(mu p)/d|v_s| [Pa] (slope of the friction law, for step control)
  int iterations = 0;
};

struct SlideProblem {
  double sat_p;      ///< sat(p) p [Pa]
  double t2x, t2y;   ///< squared trial stress components [Pa^2]
  double dx, dy;     ///< D_x, D_y [Pa s/m]
};

/// F(z) and what the iteration needs at z.
struct SlideResidual {
  double f;       ///< F [-]
  double dfdz;    ///< dF/dz [-]
  double s;       ///< |v_s| = exp(z) [m/s]
  double mup;     ///< mu(|v_s|, p) p [Pa]
  double s_dmup;  ///< |v_s| d(mu p)/d|v_s| [Pa]
};

/// mu p and |v_s| d(mu p)/d|v_s| at z = ln|v_s| (Eq 10 times sat(p) p).
inline void frictionAt(const SavkoorLog& sk, double sat_p, double z, double* mup, double* s_dmup) {
  const double l = z - sk.ln_vm;
  const double e = sk.dmu * std::exp(-sk.c * l * l);
  *mup = sat_p * (sk.mu_0 + e);
  *s_dmup = sat_p * e * (-2.0 * sk.c * l);
}

inline SlideResidual slideResidual(const SavkoorLog& sk, const SlideProblem& pr, double z) {
  SlideResidual r;
  r.s = std::exp(z);
  frictionAt(sk, pr.sat_p, z, &r.mup, &r.s_dmup);
  const double gx = pr.dx * r.s + r.mup, gy = pr.dy * r.s + r.mup;
  const double inv = 1.0 / (gx * gy);  // one division for both reciprocals
  const double igx = gy * inv, igy = gx * inv;
  const double rx = pr.t2x * igx * igx, ry = pr.t2y * igy * igy;
  r.dfdz = -2.0 * (rx * (pr.dx * r.s + r.s_dmup) * igx + ry * (pr.dy * r.s + r.s_dmup) * igy);
  r.f = rx + ry - 1.0;
  return r;
}

/// The slide root as a resumable iteration: start(), then residual at z() and update() until update()
/// returns true. Split this way so that the roots of all strips of an x step are iterated side by side:
/// one root is a chain of exp, division and exp that the processor cannot shorten, but the chains of
/// different strips are independent and overlap (docs/performance.md).
class SlideIteration {
 public:
  /// Creep test and starting point. True when done without iterating (creep at the static limit).
  bool start(const SavkoorLog& sk, const SlideProblem& pr, double z_floor, double f_floor_mu, double z_guess,
             bool have_guess) {
    root_ = SlideRoot{};
    {  // Creep test at the floor speed: there D s is negligible against mu p and mu = mu(floor) (constant).
      const double mup = pr.sat_p * f_floor_mu;
      if ((pr.t2x + pr.t2y) <= mup * mup) return true;
    }
    // Bracket [z_lo, z_hi]; the a-priori upper end ln(|t| / min D) is only computed if bisection needs it.
    z_lo_ = z_floor;
    z_hi_ = std::numeric_limits<double>::infinity();
    z_ = z_guess;
    if (!have_guess || z_guess < sk.ln_vm) {
      const double r = std::sqrt(pr.t2x + pr.t2y);
      // Closed-form creep root mu(s) p = r with D s neglected, on the rising branch (s < v_m): there it
      // is a better start than the warm start; beyond the peak of mu the warm start is.
      const double e = (r / pr.sat_p - sk.mu_0) / sk.dmu;
      if (e > 0.0 && e < 1.0) {
        z_ = sk.ln_vm - std::sqrt(-std::log(e) / sk.c);
      } else if (!have_guess) {  // viscous estimate: D s carries what friction at its floor mu_0 p does not
        const double s_visc = std::sqrt(pr.t2x / (pr.dx * pr.dx) + pr.t2y / (pr.dy * pr.dy));
        z_ = std::log(std::max(s_visc * (1.0 - pr.sat_p * sk.mu_0 / r), 1e-300));
      }
    }
    if (!(z_ > z_lo_ && z_ < z_hi_)) z_ = 0.5 * (z_lo_ + upperEnd(pr));
    return false;
  }

  double z() const { return z_; }

  /// One safeguarded Newton step from the residual at z(). True when the root is found.
  bool update(const SavkoorLog& sk, const SlideProblem& pr, const SlideResidual& r, double tol, int max_iterations) {
    root_.iterations += 1;
    if (r.f > 0.0) z_lo_ = z_; else z_hi_ = z_;
    // Far from the root F + 1 behaves like a power of s (like s^-2 where D s dominates), so Newton
    // on ln(F + 1) is nearly linear in z there; near the root both forms agree to O(F^2).
    const bool descending = r.dfdz < 0.0;
    const double step = !descending ? 0.0 : (std::fabs(r.f) < 0.25 ? -r.f : -(1.0 + r.f) * std::log1p(r.f)) / r.dfdz;
    if (descending && std::fabs(step) < tol) {
      // Quadratic convergence: the remaining error is O(step^2); correct s and mu p to first order.
      root_.z = z_ + step;
      root_.s = r.s * (1.0 + step);
      root_.mup = r.mup + r.s_dmup * step;
      root_.s_dmup = r.s_dmup;
      return true;
    }
    double z_new = z_ + step;
    if (!descending || !(z_new > z_lo_ && z_new < z_hi_)) z_new = 0.5 * (z_lo_ + upperEnd(pr));
    if (z_hi_ - z_lo_ < tol || root_.iterations == max_iterations) {
      root_.z = z_new;
      root_.s = std::exp(z_new);
      frictionAt(sk, pr.sat_p, z_new, &root_.mup, &root_.s_dmup);
      return true;
    }
    z_ = z_new;
    return false;
  }

  const SlideRoot& root() const { return root_; }

 private:
  double upperEnd(const SlideProblem& pr) {
    if (std::isinf(z_hi_)) z_hi_ = std::log(std::sqrt(pr.t2x + pr.t2y) / std::min(pr.dx, pr.dy));
    return z_hi_;
  }

  double z_ = 0.0, z_lo_ = 0.0, z_hi_ = 0.0;
  SlideRoot root_;
};

/// State of the element travelling along one strip, and its values at the last node (for the
/// trapezoid correction of a refined step).
struct ElementState {
  double dlx, dly, ux, uy;          ///< deflection [m] and its rate [m/s] at the current node
  double dlx_p, dly_p, ux_p, uy_p;  ///< the same at the previous node (BDF2)
  double z;                         ///< ln|v_s| at the current node if it slid (warm start)
  double z_p;                       ///< ln|v_s| at the previous node if it slid
  bool sliding;                     ///< the current node slid with |v_s| > 0
  bool sliding_p;                   ///< the previous node slid with |v_s| > 0
  bool refined;                     ///< the last coarse step was taken in substeps
  double ds;                        ///< length of the last step taken [-] (x/a units)
  double tx, ty, wt, stick, exact;  ///< tau [Pa], wear per time and area [kg/(s m^2)], stick flags at the node
};

/// Result of one implicit step of one element.
struct NodeSolution {
  double p;              ///< pressure [Pa]
  double tx, ty;         ///< shear stress [Pa]
  double vsx, vsy;       ///< sliding velocity [m/s]
  double s, z;           ///< |v_s| [m/s] and ln|v_s| (0 when not sliding)
  double mup, s_dmup;    ///< mu p [Pa] and |v_s| d(mu p)/d|v_s| [Pa] at the slide root
  double wt;             ///< wear per time and area, Eq 19 [kg/(s m^2)]
  bool stuck;            ///< exact stick (v_s = 0)
};

/// Per-step terms of the implicit update m u' + c u + k delta = tau over the BDF2 step g = beta h.
struct StepTerms {
  double g;               ///< beta h [s]
  double m_over_g;        ///< m / g [Pa s/m]
  double dx, dy;          ///< D = m/g + c + k g [Pa s/m]
  double inv_dx, inv_dy;  ///< 1/D [m/(Pa s)]
  double w;               ///< step ratio h_i / h_{i-1} for the along-path extrapolation of ln|v_s| [-]
  Bdf2 c;                 ///< BDF2 coefficients of the step
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
  const int max_level = options_.refinement.max_level;
  const double edge_weight = 1.0 / (1.0 + w1) - 0.5;
  const int initial_budget = max_level > 0 ? options_.refinement.node_budget : 0;
  int refinement_budget = initial_budget;

  std::array<ElementState, GridSpec::kMaxStrips> el;
  // Per x step: each strip's state at node i (for substeps), its wear there, its step terms and its node solution.
  std::array<ElementState, GridSpec::kMaxStrips> before;
  std::array<double, GridSpec::kMaxStrips> wt_prev;
  std::array<StepTerms, GridSpec::kMaxStrips> back;
  std::array<const StepTerms*, GridSpec::kMaxStrips> step_terms;
  std::array<NodeSolution, GridSpec::kMaxStrips> nodes;
  std::array<int, GridSpec::kMaxStrips> all_strips;
  double strip_weight[GridSpec::kMaxStrips];  // area weight factor of a marched strip (2 for mirrored pairs)
  for (int j = 0; j < n_active; ++j) {
    all_strips[j] = j;
    strip_weight[j] = (mirror && 2 * j + 1 != ny) ? 2.0 : 1.0;
    ElementState& e = el[j];
    e = ElementState{};
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

  auto store = [&](int i, int j, const NodeSolution& o) {
    const ElementState& e = el[j];
    const unsigned char st = o.stuck ? 0 : (o.s <= v_m ? 1 : 2);
    for (int jj : {j, ny - 1 - j}) {
      const int k = fields->index(i, jj);
      fields->pressure_pa[k] = o.p;
      fields->tau_x_pa[k] = o.tx;
      fields->tau_y_pa[k] = o.ty;
      fields->v_sx_mps[k] = o.vsx;
      fields->v_sy_mps[k] = o.vsy;
      fields->delta_x_m[k] = e.dlx;
      fields->delta_y_m[k] = e.dly;
      fields->wear_kg_per_m3[k] = o.wt / V;
      fields->state[k] = st;
      if (!mirror) break;
    }
  };

  // Implicit terms of a step of length ds [x/a] with BDF2 coefficients c.
  auto stepTerms = [&](double ds, const Bdf2& c, double w) {
    StepTerms t;
    t.c = c;
    t.w = w;
    t.g = c.beta * a * ds / Vr;
    t.m_over_g = m / t.g;
    t.dx = t.m_over_g + cx + kx * t.g;
    t.dy = t.m_over_g + cy + ky * t.g;
    t.inv_dx = 1.0 / t.dx;
    t.inv_dy = 1.0 / t.dy;
    return t;
  };

  // Pressure factor p / g_y [Pa] and the x factor of sat(p) at node coordinate s = x/a.
  auto pressureX = [&](double s, double gx_even, double* sat_x) {
    const double px = std::max(0.0, p_scale * gx_even * (1.0 - Bx * s));
    *sat_x = px > 0.0 ? std::pow(px / fr.p_ref_pa, -fr.q) : 0.0;
    return px;
  };

  // Per-strip work of one implicit step, kept across the phases of advanceStrips.
  struct StripWork {
    double y;                 // strip centre [m]
    double sat_p;             // sat(p) p [Pa]
    double tau_static;        // static limit mu_0 sat(p) p [Pa]
    double dhx, dhy;          // BDF2 history of delta [m]
    double bx, by;            // history terms of the implicit update [Pa]
    double ndx, ndy;          // deflection at the new node (predictor, then corrector) [m]
    double ttx, tty;          // trial stress [Pa]
    SlideProblem problem;
    SlideIteration root;
  };
  std::array<StripWork, GridSpec::kMaxStrips> work;
  std::array<int, GridSpec::kMaxStrips> solving;
  std::array<SlideResidual, GridSpec::kMaxStrips> residuals;

  // One implicit step of the elements of `count` strips (strip[k], with step terms *terms[k]) to the
  // node at x [m] (return mapping, Eqs 17-18, and the wear law Eq 19); updates their states and writes
  // their node solutions to out[k]. The strips go through each phase together, and their slide roots
  // are iterated side by side (SlideIteration).
  auto advanceStrips = [&](int count, const int* strip, const StepTerms* const* terms, double x, double px,
                           double sat_x, NodeSolution* out) {
    for (int k = 0; k < count; ++k) {
      const int j = strip[k];
      const ElementState& e = el[j];
      const StepTerms& st = *terms[k];
      StripWork& wk = work[k];
      NodeSolution& o = out[k];
      wk.y = b * eta_[j];
      o.p = px * gy_[j];
      const double sat = o.p > fr.p_0_pa ? sat_x * sat_y_[j] : sat_floor;
      wk.sat_p = sat * o.p;
      wk.tau_static = fr.mu_0 * wk.sat_p;
      wk.dhx = st.c.a1 * e.dlx + st.c.a2 * e.dlx_p;
      wk.dhy = st.c.a1 * e.dly + st.c.a2 * e.dly_p;
      const double uhx = st.c.a1 * e.ux + st.c.a2 * e.ux_p, uhy = st.c.a1 * e.uy + st.c.a2 * e.uy_p;
      wk.bx = st.m_over_g * uhx - kx * wk.dhx;
      wk.by = st.m_over_g * uhy - ky * wk.dhy;
      wk.ndx = wk.dhx + st.g * e.ux;  // predictor for the Omega delta coupling
      wk.ndy = wk.dhy + st.g * e.uy;
      o.tx = o.ty = o.vsx = o.vsy = o.s = o.mup = o.s_dmup = o.z = 0.0;
      o.stuck = false;
    }
    for (int pass = 0; pass < passes; ++pass) {
      int n_solving = 0;
      for (int k = 0; k < count; ++k) {
        const ElementState& e = el[strip[k]];
        const StepTerms& st = *terms[k];
        StripWork& wk = work[k];
        NodeSolution& o = out[k];
        const double rx = vrx0 + Omega * (wk.y + wk.ndy), ry = vry0 - Omega * (x + wk.ndx);
        wk.ttx = st.dx * rx - wk.bx;  // stress needed to stick
        wk.tty = st.dy * ry - wk.by;
        const double t2x = wk.ttx * wk.ttx, t2y = wk.tty * wk.tty;
        o.stuck = t2x + t2y <= wk.tau_static * wk.tau_static;
        if (o.stuck) {
          o.tx = wk.ttx;
          o.ty = wk.tty;
          o.s = o.vsx = o.vsy = o.z = 0.0;
          continue;
        }
        // Warm start: the previous pass at this node, else ln|v_s| extrapolated along the element path.
        const bool have_guess = o.s > 0.0 || e.sliding;
        const double guess = o.s > 0.0 ? o.z : (e.sliding_p ? e.z + st.w * (e.z - e.z_p) : e.z);
        wk.problem = SlideProblem{wk.sat_p, t2x, t2y, st.dx, st.dy};
        if (!wk.root.start(sk, wk.problem, z_floor, savkoor_floor, guess, have_guess)) solving[n_solving++] = k;
      }
      while (n_solving > 0) {  // the residuals of all unfinished roots first: independent of each other
        for (int q = 0; q < n_solving; ++q) {
          const StripWork& wk = work[solving[q]];
          residuals[q] = slideResidual(sk, wk.problem, wk.root.z());
        }
        int still = 0;
        for (int q = 0; q < n_solving; ++q) {
          StripWork& wk = work[solving[q]];
          if (!wk.root.update(sk, wk.problem, residuals[q], tol, max_it)) solving[still++] = solving[q];
        }
        n_solving = still;
      }
      for (int k = 0; k < count; ++k) {
        const StepTerms& st = *terms[k];
        StripWork& wk = work[k];
        NodeSolution& o = out[k];
        if (!o.stuck) {
          const SlideRoot& root = wk.root.root();
          max_iterations = std::max(max_iterations, root.iterations);
          total_iterations += root.iterations;
          o.s = root.s;
          if (o.s > 0.0) {
            o.mup = root.mup;
            o.s_dmup = root.s_dmup;
            o.z = root.z;
            const double gx = st.dx * o.s + o.mup, gy = st.dy * o.s + o.mup;
            const double inv = 1.0 / (gx * gy);
            const double igx = gy * inv, igy = gx * inv;
            o.vsx = -wk.ttx * o.s * igx;
            o.vsy = -wk.tty * o.s * igy;
            o.tx = o.mup * wk.ttx * igx;
            o.ty = o.mup * wk.tty * igy;
          } else {  // creep at the static limit along the trial direction
            const double tt = std::sqrt(wk.ttx * wk.ttx + wk.tty * wk.tty);
            o.vsx = o.vsy = o.z = 0.0;
            o.tx = wk.tau_static * wk.ttx / tt;
            o.ty = wk.tau_static * wk.tty / tt;
          }
        }
        const double nux = (o.tx + wk.bx) * st.inv_dx, nuy = (o.ty + wk.by) * st.inv_dy;
        wk.ndx = wk.dhx + st.g * nux;
        wk.ndy = wk.dhy + st.g * nuy;
        if (pass + 1 == passes) {
          ElementState& e = el[strip[k]];
          e.dlx_p = e.dlx;
          e.dly_p = e.dly;
          e.ux_p = e.ux;
          e.uy_p = e.uy;
          e.dlx = wk.ndx;
          e.dly = wk.ndy;
          e.ux = nux;
          e.uy = nuy;
          e.sliding_p = e.sliding;
          e.z_p = e.z;
          e.sliding = o.s > 0.0;
          e.z = o.z;
        }
      }
    }
    // Eq 19 per time; at the slide root |tau| = mu p exactly, and ln|v_s| = z is known. Below z_wear_cut
    // the sliding term is under 1e-9 w4 (deep creep) and is skipped.
    for (int k = 0; k < count; ++k) {
      NodeSolution& o = out[k];
      o.wt = (o.s > 0.0 && o.z > z_wear_cut) ? w4 + std::exp(ln_w3_over_mpa_w1 + w1 * std::log(o.mup) + w2 * o.z) : w4;
    }
  };

  // Substeps needed in a step of duration h [s] that ended in o: sliding on the velocity-weakening
  // branch with little effective damping c + d(mu p)/d|v_s| along the slip makes the element oscillate
  // or run away (stick-slip bursts) on its own time scale, which the step must resolve.
  auto refinementLevel = [&](const NodeSolution& o, double h) {
    if (!(o.s > v_m)) return 0;
    const double nx2 = o.vsx * o.vsx / (o.s * o.s), ny2 = 1.0 - nx2;
    const double k_dir = kx * nx2 + ky * ny2;
    const double c_eff = cx * nx2 + cy * ny2 + o.s_dmup / o.s;
    const double c_crit = 2.0 * std::sqrt(m * k_dir);
    if (c_eff >= options_.refinement.damping_ratio * c_crit) return 0;
    const double rate = std::max(std::sqrt(k_dir / m), -c_eff / m);  // [1/s]
    const double r = rate * h / options_.refinement.resolution;
    if (r <= 1.0) return 0;
    return std::min(max_level, static_cast<int>(std::ceil(std::log2(r))));
  };

  {  // Leading edge: p = 0, no friction; the element slips at u - v_r.
    const double w0 = wx_[0] * a * b;
    for (int j = 0; j < n_active; ++j) {
      ElementState& e = el[j];
      const double y = b * eta_[j];
      NodeSolution o{};
      o.vsx = e.ux - (vrx0 + Omega * y);
      o.vsy = e.uy - (vry0 - Omega * a);
      o.s = std::sqrt(o.vsx * o.vsx + o.vsy * o.vsy);
      o.wt = w4;
      o.stuck = o.s == 0.0;
      const double w = w0 * wy_[j] * strip_weight[j];
      e.wt = w4;
      e.stick = o.s <= v_m ? 1.0 : 0.0;
      e.exact = o.stuck ? 1.0 : 0.0;
      wear_t += w4 * w;
      stick_area += e.stick * w;
      exact_area += e.exact * w;
      if (fields) store(0, j, o);
    }
  }

  for (int i = 0; i < n; ++i) {
    const Step& sp = steps_[i];
    const StepTerms coarse = stepTerms(sp.ds, Bdf2{sp.a1, sp.a2, sp.beta}, sp.w);
    const double h = a * sp.ds / Vr;  // step duration [s]
    const double x = a * s_[i + 1];
    double sat_x;
    const double px = pressureX(s_[i + 1], gx_even_[i + 1], &sat_x);
    const double wxa = wx_[i + 1] * a * b;
    const bool edge_step = i == 0 || i == n - 1;
    // Sums over strips of the node values (weight wx) and of the corrections of refined steps (x/a units).
    double fx_i = 0.0, fy_i = 0.0, mz_y = 0.0, wear_i = 0.0, stick_i = 0.0, exact_i = 0.0;
    double cfx = 0.0, cfy = 0.0, cmz = 0.0, cwear = 0.0, cstick = 0.0, cexact = 0.0;
    // All strips advance to node i + 1 together; a step is then redone in substeps strip by strip.
    const bool may_refine = refinement_budget > 0;
    for (int j = 0; j < n_active; ++j) {
      ElementState& e = el[j];
      wt_prev[j] = e.wt;
      if (may_refine) before[j] = e;  // the state at node i, kept only while a step may be redone in substeps
      // After substeps the step ratio is 2^level; variable-step BDF2 is zero-stable only below
      // 1 + sqrt(2), so a larger jump restarts with one BDF1 step.
      if (e.refined) {
        const double w_back = sp.ds / e.ds;
        back[j] = stepTerms(sp.ds, bdf2Coefficients(w_back > 2.0 ? 0.0 : w_back), w_back);
        step_terms[j] = &back[j];
      } else {
        step_terms[j] = &coarse;
      }
    }
    advanceStrips(n_active, all_strips.data(), step_terms.data(), x, px, sat_x, nodes.data());
    for (int j = 0; j < n_active; ++j) {
      ElementState& e = el[j];
      NodeSolution& o = nodes[j];
      int level = refinement_budget > 0 ? refinementLevel(o, h) : 0;
      while (level > 0 && (1 << level) > refinement_budget) --level;  // never beyond the node budget
      const double w = wy_[j] * strip_weight[j];
      const double y = b * eta_[j];
      const double y_mz = mirror ? 0.0 : y;  // the y tau_x terms of mirrored pairs cancel
      double wt_lead = o.wt, wt_trail = wt_prev[j], edge_ds = sp.ds;  // wear next to an edge of the patch
      if (level > 0) {
        // Redo the step in 2^level equal substeps ending on the node; integrate the strip's outputs over
        // them by the trapezoid rule and add the difference to the coarse trapezoid of this step.
        const int k_sub = 1 << level;
        refinement_budget -= k_sub;
        const double dss = sp.ds / k_sub;
        const double w_in = before[j].ds > 0.0 ? dss / before[j].ds : 0.0;
        e = before[j];
        double tx0 = e.tx, ty0 = e.ty, wt0 = e.wt, st0 = e.stick, ex0 = e.exact, x0 = a * s_[i];
        double ifx = 0.0, ify = 0.0, imz = 0.0, iw = 0.0, ist = 0.0, iex = 0.0;
        const StepTerms first = stepTerms(dss, bdf2Coefficients(w_in), w_in);
        const StepTerms inner = stepTerms(dss, bdf2Coefficients(1.0), 1.0);
        for (int k = 1; k <= k_sub; ++k) {
          const double s_k = s_[i] - k * dss;  // substep node x/a
          double sat_k = sat_x, px_k = px, x_k = x;
          if (k < k_sub) {
            px_k = pressureX(s_k, gx_.even(s_k), &sat_k);
            x_k = a * s_k;
          }
          const StepTerms* terms = k == 1 ? &first : &inner;
          advanceStrips(1, &j, &terms, x_k, px_k, sat_k, &o);
          const double st1 = o.s <= v_m ? 1.0 : 0.0, ex1 = o.stuck ? 1.0 : 0.0;
          ifx += 0.5 * dss * (tx0 + o.tx);
          ify += 0.5 * dss * (ty0 + o.ty);
          imz += 0.5 * dss * (x0 * ty0 - y_mz * tx0 + x_k * o.ty - y_mz * o.tx);
          iw += 0.5 * dss * (wt0 + o.wt);
          ist += 0.5 * dss * (st0 + st1);
          iex += 0.5 * dss * (ex0 + ex1);
          if (k == 1) wt_lead = o.wt;
          if (k == k_sub) wt_trail = wt0;
          tx0 = o.tx, ty0 = o.ty, wt0 = o.wt, st0 = st1, ex0 = ex1, x0 = x_k;
        }
        edge_ds = dss;
        const double hds = 0.5 * sp.ds;
        const double st1 = o.s <= v_m ? 1.0 : 0.0, ex1 = o.stuck ? 1.0 : 0.0;
        cfx += w * (ifx - hds * (before[j].tx + o.tx));
        cfy += w * (ify - hds * (before[j].ty + o.ty));
        cmz += w * (imz - hds * (a * s_[i] * before[j].ty - y_mz * before[j].tx + x * o.ty - y_mz * o.tx));
        cwear += w * (iw - hds * (before[j].wt + o.wt));
        cstick += w * (ist - hds * (before[j].stick + st1));
        cexact += w * (iex - hds * (before[j].exact + ex1));
        e.refined = true;
        e.ds = dss;
      } else if (initial_budget > 0) {
        e.refined = false;
        e.ds = sp.ds;
      }
      const double stick = o.s <= v_m ? 1.0 : 0.0, exact = o.stuck ? 1.0 : 0.0;
      e.wt = o.wt;
      if (initial_budget > 0) {  // node values for the trapezoid correction of a later refined step
        e.tx = o.tx;
        e.ty = o.ty;
        e.stick = stick;
        e.exact = exact;
      }
      // p vanishes linearly at x = +-a, so the sliding wear ~ tau^w1 ~ p^w1 has an endpoint singularity
      // there: on the interval next to an edge its integral is h f/(1 + w1), not the trapezoid's h f/2.
      if (edge_step) cwear += w * edge_weight * edge_ds * ((i == 0 ? wt_lead : wt_trail) - w4);
      fx_i += o.tx * w;
      fy_i += o.ty * w;
      if (!mirror) mz_y += y * o.tx * w;
      wear_i += o.wt * w;
      stick_i += stick * w;
      exact_i += exact * w;
      if (fields) store(i + 1, j, o);
    }
    const double ab = a * b;
    fx += fx_i * wxa + cfx * ab;
    fy += fy_i * wxa + cfy * ab;
    mz += (x * fy_i - mz_y) * wxa + cmz * ab;
    wear_t += wear_i * wxa + cwear * ab;
    stick_area += stick_i * wxa + cstick * ab;
    exact_area += exact_i * wxa + cexact * ab;
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
  result->refined_substeps = initial_budget - refinement_budget;
}

}  // namespace tread_wear
