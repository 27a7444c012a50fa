#include "tread_wear/model/brush_wear_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "brush_march.h"
#include "tread_wear/model/quadrature.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {

bool GridSpec::validate(std::string* error) const {
  if (n_x_steps < 4) return failValidation(error, "grid.n_x_steps", n_x_steps, ">= 4");
  if (n_strips < 1 || n_strips > kMaxStrips)
    return failValidation(error, "grid.n_strips", n_strips, "in [1, " + std::to_string(kMaxStrips) + "]");
  if (lateral_rule == LateralRule::kGaussShoulderPanels && (n_strips < 6 || n_strips % 2 != 0))
    return failValidation(error, "grid.n_strips", n_strips, "even and >= 6 with shoulder panels");
  if (!(edge_grading >= 0.0 && edge_grading < 1.0))
    return failValidation(error, "grid.edge_grading", edge_grading, "in [0, 1)");
  if (!(entry_transit_periods >= 0.0) || !std::isfinite(entry_transit_periods))
    return failValidation(error, "grid.entry_transit_periods", entry_transit_periods, "finite and >= 0");
  if (!(entry_grading >= 0.0 && entry_grading < 1.0))
    return failValidation(error, "grid.entry_grading", entry_grading, "in [0, 1)");
  if (entry_strips < 0 || entry_strips > kMaxStrips)
    return failValidation(error, "grid.entry_strips", entry_strips, "in [0, " + std::to_string(kMaxStrips) + "]");
  if (entry_strips > 0 && lateral_rule == LateralRule::kGaussShoulderPanels &&
      (entry_strips < 6 || entry_strips % 2 != 0))
    return failValidation(error, "grid.entry_strips", entry_strips, "0, or even and >= 6 with shoulder panels");
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
  if (max_simd_lanes != 1 && max_simd_lanes != 2 && max_simd_lanes != 4)
    return failValidation(error, "max_simd_lanes", max_simd_lanes, "1, 2 or 4");
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

/// g^-q for a pressure shape value g (x or y factor of sat(p), Eq 11: (p/p_ref)^-q separates with p); 0 where
/// g = 0 (the edge, where p = 0 and sat(p) is the floor's anyway).
double shapeSaturation(double g, double q) { return g > 0.0 ? std::pow(g, -q) : 0.0; }

using march::Bdf2;

/// BDF2 coefficients for the step ratio w = h_i / h_{i-1}; w = 0 gives BDF1 (a restart).
Bdf2 bdf2Coefficients(double w) {
  const double d = 1.0 / (1.0 + 2.0 * w);
  return {(1.0 + w) * (1.0 + w) * d, -w * w * d, (1.0 + w) * d};
}

}  // namespace

BrushWearModel::BrushWearModel(const TireParams& params, const BrushOptions& options)
    : params_(params),
      options_(options),
      friction_(params.friction),
      shift_saturation_(params.friction.q),
      advance_(march::fastestAdvance(options.max_simd_lanes)) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid tire parameters: " + error);
  if (!options.validate(&error)) throw std::invalid_argument("invalid brush options: " + error);

  gx_ = PressureShape(params.footprint.n_x, params.footprint.lambda_x, 0.0);
  x_grid_ = makeXGrid(options.grid.edge_grading);
  if (options.grid.entry_transit_periods > 0.0) entry_x_grid_ = makeXGrid(options.grid.entry_grading);

  y_grid_ = makeYGrid(options.grid.n_strips);
  if (options.grid.entry_transit_periods > 0.0 && options.grid.entry_strips > 0 &&
      options.grid.entry_strips != options.grid.n_strips)
    entry_y_grid_ = makeYGrid(options.grid.entry_strips);
}

int BrushWearModel::strips() const {
  return static_cast<int>(std::max(y_grid_.eta.size(), entry_y_grid_.eta.size()));
}

BrushWearModel::YGrid BrushWearModel::makeYGrid(int n_strips) const {
  YGrid g;
  g.eta.resize(n_strips);
  g.wy.resize(n_strips);
  g.gy.resize(n_strips);
  g.sat_y.resize(n_strips);
  const FootprintParams& fp = params_.footprint;
  const PressureShape gy(fp.n_y, fp.lambda_y, fp.y_e_m / fp.b_m);
  if (options_.grid.lateral_rule == LateralRule::kGaussShoulderPanels) {
    shoulderPanels(n_strips, fp.n_y, &g.eta, &g.wy);
  } else if (options_.grid.lateral_rule == LateralRule::kGaussLegendre) {
    gaussLegendre(n_strips, &g.eta, &g.wy);
  } else {
    auto map = [](double t) { return std::sin(0.5 * units::kPi * t); };  // clusters strips at the shoulders
    for (int j = 0; j < n_strips; ++j) {
      const double t0 = -1.0 + 2.0 * j / n_strips, t1 = -1.0 + 2.0 * (j + 1) / n_strips;
      g.eta[j] = map(0.5 * (t0 + t1));
      g.wy[j] = map(t1) - map(t0);
    }
    if (n_strips % 2 == 1) g.eta[n_strips / 2] = 0.0;
  }
  for (int j = 0; j < n_strips; ++j) {
    g.gy[j] = gy(g.eta[j]);
    g.sat_y[j] = shapeSaturation(g.gy[j], params_.friction.q);
  }
  g.symmetric = fp.y_e_m == 0.0;
  for (int j = 0, k = n_strips - 1; j < n_strips && g.symmetric; ++j, --k)
    g.symmetric = g.eta[j] == -g.eta[k] && g.wy[j] == g.wy[k] && g.gy[j] == g.gy[k];
  return g;
}

BrushWearModel::XGrid BrushWearModel::makeXGrid(double leading_grading) const {
  const int n = options_.grid.n_x_steps;
  XGrid g;
  g.s.resize(n + 1);
  for (int i = 0; i <= n; ++i) {
    const double u = 1.0 - 2.0 * i / n;  // uniform, leading edge first
    const double grading = u > 0.0 ? leading_grading : options_.grid.edge_grading;
    g.s[i] = (1.0 - grading) * u + grading * std::sin(0.5 * units::kPi * u);
  }
  g.s.front() = 1.0;
  g.s.back() = -1.0;
  g.wx.assign(n + 1, 0.0);
  g.steps.resize(n);
  for (int i = 0; i < n; ++i) {
    const double ds = g.s[i] - g.s[i + 1];
    g.wx[i] += 0.5 * ds;
    g.wx[i + 1] += 0.5 * ds;
    // BDF1 on the first step, then variable-step BDF2 (w = h_i / h_{i-1} = ds_i / ds_{i-1}).
    const double w = i > 0 ? ds / (g.s[i - 1] - g.s[i]) : 0.0;
    const Bdf2 c = bdf2Coefficients(w);
    g.steps[i] = Step{ds, c.a1, c.a2, c.beta, i > 0 ? w : 1.0};
  }
  g.gx_even.resize(n + 1);
  g.sat_gx.resize(n + 1);
  for (int i = 0; i <= n; ++i) {
    g.gx_even[i] = gx_.even(g.s[i]);
    g.sat_gx[i] = shapeSaturation(g.gx_even[i], params_.friction.q);
  }
  const int fine = 1 << options_.refinement.max_level;  // substeps of the finest level per step
  g.sub_gx_even.resize(static_cast<size_t>(n) * (fine - 1));
  g.sub_sat_gx.resize(g.sub_gx_even.size());
  for (int i = 0; i < n; ++i)
    for (int m = 1; m < fine; ++m) {
      const size_t k = static_cast<size_t>(i) * (fine - 1) + (m - 1);
      g.sub_gx_even[k] = gx_.even(g.s[i] - m * (g.steps[i].ds / fine));
      g.sub_sat_gx[k] = shapeSaturation(g.sub_gx_even[k], params_.friction.q);
    }
  return g;
}

bool BrushWearModel::entryTransient(double half_length_m, double kx_pa_per_m, double rolling_speed_mps) const {
  const double periods = options_.grid.entry_transit_periods;
  if (!(periods > 0.0)) return false;
  const double period = 2.0 * units::kPi * std::sqrt(params_.tread.m_kg_per_m2 / kx_pa_per_m);  // [s]
  const double transit = 2.0 * half_length_m / rolling_speed_mps;                               // [s]
  return transit <= periods * period;
}

namespace {

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

/// Integrands of Eq 20 and of the area fractions at a node, or their weighted sums: tau_x, tau_y [Pa],
/// x tau_y - y tau_x [Pa m], wear per time and area [kg/(s m^2)], the stick (|v_s| <= v_m) and exact-stick
/// (v_s = 0) indicators [-].
struct Integrands {
  double fx = 0.0, fy = 0.0, mz = 0.0, wear = 0.0, stick = 0.0, exact = 0.0;

  void add(double weight, const Integrands& v) {
    fx += weight * v.fx;
    fy += weight * v.fy;
    mz += weight * v.mz;
    wear += weight * v.wear;
    stick += weight * v.stick;
    exact += weight * v.exact;
  }
};

NodeSolution nodeOf(const march::NodeLanes& n, int j) {
  return {n.p[j], n.tx[j], n.ty[j], n.vsx[j], n.vsy[j], n.s[j], n.z[j], n.mup[j], n.s_dmup[j], n.wt[j],
          n.stuck[j] != 0.0};
}

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
  // The integrands of node solution o at x [m] on the strip with Mz lever arm y_mz [m]; stick by the paper's
  // Section 4 definition (|v_s| <= v_m).
  auto integrands = [v_m](const NodeSolution& o, double x, double y_mz) {
    return Integrands{o.tx, o.ty, x * o.ty - y_mz * o.tx, o.wt, o.s <= v_m ? 1.0 : 0.0, o.stuck ? 1.0 : 0.0};
  };
  // ln|v_s| below which w3 (|tau|/1 MPa)^w1 |v_s|^w2 < 1e-9 w4 for any |tau| <= 100 MPa.
  const double z_wear_cut = w4 > 0.0 ? (std::log(1e-9 * w4) - ln_w3_over_mpa_w1 - w1 * std::log(100e6)) / w2
                                     : -std::numeric_limits<double>::infinity();
  const double p_scale = Fz / (2.0 * a) / (2.0 * b);  // p = p_scale g_x g_y
  const double sat_floor = friction_.saturation(fr.p_0_pa);
  const bool entry = entryTransient(a, kx, Vr);
  const XGrid& xg = entry ? entry_x_grid_ : x_grid_;
  const YGrid& yg = entry && !entry_y_grid_.eta.empty() ? entry_y_grid_ : y_grid_;
  const int n = static_cast<int>(xg.s.size()) - 1;
  const int ny = static_cast<int>(yg.eta.size());
  // Mirror symmetry in y: v_r does not depend on y without turn slip, and g_y is even.
  const bool mirror = options_.use_symmetry && yg.symmetric && Omega == 0.0;
  const int n_active = mirror ? (ny + 1) / 2 : ny;
  const int passes = Omega == 0.0 ? 1 : options_.turn_slip_iterations;

  const int max_level = options_.refinement.max_level;
  const double edge_weight = 1.0 / (1.0 + w1) - 0.5;
  const int initial_budget = max_level > 0 ? options_.refinement.node_budget : 0;
  int refinement_budget = initial_budget;
  march::Constants constants;
  constants.vrx0 = vrx0;
  constants.vry0 = vry0;
  constants.omega = Omega;
  constants.kx = kx;
  constants.ky = ky;
  constants.p_0 = fr.p_0_pa;
  constants.sat_floor = sat_floor;
  constants.mu_0 = fr.mu_0;
  constants.dmu = fr.mu_m - fr.mu_0;
  constants.savkoor_c = fr.h * fr.h / (std::log(10.0) * std::log(10.0));
  constants.ln_vm = std::log(v_m);
  constants.z_floor = std::log(options_.creep_floor_mps);
  constants.savkoor_floor = friction_.savkoor(options_.creep_floor_mps);
  constants.tol = options_.root_tolerance;
  constants.max_iterations = options_.max_root_iterations;
  constants.passes = passes;
  constants.w1 = w1;
  constants.w2 = w2;
  constants.w4 = w4;
  constants.ln_w3_over_mpa_w1 = ln_w3_over_mpa_w1;
  constants.z_wear_cut = z_wear_cut;
  constants.v_m = v_m;
  constants.refine = initial_budget > 0;
  constants.m = m;
  constants.cx = cx;
  constants.cy = cy;
  constants.damping_ratio = options_.refinement.damping_ratio;

  // Per-strip state and per x step work, structure of arrays (march::advance* run packs of strips
  // on them); the strips from n_active to the end of the last pack are zero and never read back.
  const int n_padded = std::min(n_active + march::kMaxLanes, march::kCapacity);
  // Two path states, at node i and at node i + 1, swapped after each x step: a step redone in
  // substeps starts again from node i without a copy.
  march::PathState paths[2];
  march::PathState* el = &paths[0];
  march::PathState* next = &paths[1];
  // Node solutions at node i and at node i + 1, swapped after each x step: those at node i are the
  // start of the trapezoid correction of a step redone in substeps.
  march::NodeLanes node_buffers[2];
  march::NodeLanes* prev_nodes = &node_buffers[0];
  march::NodeLanes* nodes = &node_buffers[1];
  march::StripConstants strip_constants;
  // Of a strip whose step was redone in substeps: the last such step and its substep length [x/a]; the
  // number of strips redone in the previous step.
  int refined_step[GridSpec::kMaxStrips];
  double substep_ds[GridSpec::kMaxStrips];
  int level[GridSpec::kMaxStrips];  // of the current step: 2^level substeps, 0 where it stands
  int n_back = 0;
  // Per x step: step terms of strips coming back from substeps. The quadrature sums of the packs.
  march::StepTermLanes back;
  march::PatchSums sums{};
  for (int j = 0; j < n_padded; ++j) {
    const bool active = j < n_active;
    const double mirror_factor = (mirror && 2 * j + 1 != ny) ? 2.0 : 1.0;  // a mirrored pair counts twice
    strip_constants.weight[j] = active ? yg.wy[j] * mirror_factor : 0.0;
    strip_constants.y_mz[j] = active && !mirror ? b * yg.eta[j] : 0.0;
    strip_constants.y[j] = active ? b * yg.eta[j] : 0.0;
    strip_constants.gy[j] = active ? yg.gy[j] : 0.0;
    strip_constants.sat_y[j] = active ? yg.sat_y[j] : 0.0;
    for (auto field : march::kStateFields) (el->*field)[j] = 0.0;
    el->ux[j] = active && options_.enter_at_road_velocity ? vrx0 + Omega * b * yg.eta[j] : 0.0;
    el->uy[j] = active && options_.enter_at_road_velocity ? vry0 - Omega * a : 0.0;
  }
  for (int j = 0; j < n_active; ++j) refined_step[j] = -2;  // none
  march::RootCounts root_counts;

  Integrands total;  // the integrals of Eq 20 and the stick areas: N, N m, kg/s, m^2
  if (fields) {
    for (int i = 0; i <= n; ++i) fields->x_m[i] = a * xg.s[i];
    fields->n_strips = ny;
    for (int j = 0; j < ny; ++j) fields->y_m[j] = b * yg.eta[j];
  }

  auto store = [&](int i, int j, const NodeSolution& o, const march::PathState& state) {
    const unsigned char st = o.stuck ? 0 : (o.s <= v_m ? 1 : 2);
    for (int jj : {j, ny - 1 - j}) {
      const int k = fields->index(i, jj);
      fields->pressure_pa[k] = o.p;
      fields->tau_x_pa[k] = o.tx;
      fields->tau_y_pa[k] = o.ty;
      fields->v_sx_mps[k] = o.vsx;
      fields->v_sy_mps[k] = o.vsy;
      fields->delta_x_m[k] = state.dlx[j];
      fields->delta_y_m[k] = state.dly[j];
      fields->wear_kg_per_m3[k] = o.wt / V;
      fields->state[k] = st;
      if (!mirror) break;
    }
  };

  // Implicit terms of a step of length ds [x/a] with BDF2 coefficients c.
  auto stepTerms = [&](double ds, const Bdf2& c, double w) {
    march::StepTerms t;
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

  // Pressure factor p / g_y [Pa] and the x factor of sat(p) at grid node i, where (p/p_ref)^-q separates into
  // this evaluation's scale, the grid's gx_even^-q and the centre shift's (1 - Bx s)^-q (a short series, no
  // pow); the same at the substep nodes below. Computed for a chunk of nodes at a time, so that the
  // independent series of the nodes overlap instead of each waiting in the x step's chain.
  const double sat_scale = std::pow(p_scale / fr.p_ref_pa, -fr.q);
  // p / g_y and sat_x at x/a = s from the grid's gx_even and gx_even^-q there and the shift factor (1 - Bx s)^-q.
  auto pressureFrom = [&](double gx_even, double sat_gx, double s, double shift, double* sat_x) {
    const double px = std::max(0.0, p_scale * gx_even * (1.0 - Bx * s));
    *sat_x = px > 0.0 ? sat_scale * sat_gx * shift : 0.0;
    return px;
  };
  constexpr int kNodeChunk = 64;
  double chunk_px[kNodeChunk], chunk_sat[kNodeChunk];
  int chunk_first = -kNodeChunk;
  const int shift_terms = shift_saturation_.terms(std::fabs(Bx));  // |Bx s| <= |Bx| on the patch
  auto pressureAtNode = [&](int i, double* sat_x) {
    if (i >= chunk_first + kNodeChunk) {
      chunk_first = i;
      const int count = std::min(kNodeChunk, n + 1 - i);
      double shift_u[kNodeChunk], shift[kNodeChunk];
      for (int k = 0; k < count; ++k) shift_u[k] = Bx * xg.s[i + k];
      shift_saturation_(shift_u, count, shift_terms, shift);
      for (int k = 0; k < count; ++k)
        chunk_px[k] = pressureFrom(xg.gx_even[i + k], xg.sat_gx[i + k], xg.s[i + k], shift[k], &chunk_sat[k]);
    }
    *sat_x = chunk_sat[i - chunk_first];
    return chunk_px[i - chunk_first];
  };

  {  // Leading edge: p = 0, no friction; the element slips at u - v_r.
    const double w0 = xg.wx[0] * a * b;
    for (int j = 0; j < n_active; ++j) {
      const double y = b * yg.eta[j];
      const double vsx = el->ux[j] - (vrx0 + Omega * y), vsy = el->uy[j] - (vry0 - Omega * a);
      const double vs = std::sqrt(vsx * vsx + vsy * vsy);
      march::NodeLanes& o = *prev_nodes;
      o.p[j] = o.tx[j] = o.ty[j] = o.z[j] = o.mup[j] = o.s_dmup[j] = o.refine_rate[j] = 0.0;
      o.vsx[j] = vsx;
      o.vsy[j] = vsy;
      o.s[j] = vs;
      o.wt[j] = w4;
      o.stuck[j] = vs == 0.0 ? 1.0 : 0.0;
      total.add(w0 * strip_constants.weight[j], integrands(nodeOf(o, j), a, strip_constants.y_mz[j]));
      if (fields) store(0, j, nodeOf(o, j), *el);
    }
  }

  for (int i = 0; i < n; ++i) {
    const Step& sp = xg.steps[i];
    const march::StepTerms coarse = stepTerms(sp.ds, Bdf2{sp.a1, sp.a2, sp.beta}, sp.w);
    const double h = a * sp.ds / Vr;  // step duration [s]
    const double x = a * xg.s[i + 1];
    double sat_x;
    const double px = pressureAtNode(i + 1, &sat_x);
    const double wxa = xg.wx[i + 1] * a * b;
    const bool edge_step = i == 0 || i == n - 1;
    // All strips advance to node i + 1 together; then runs of neighbouring strips that need the same number of
    // substeps redo the step together, in packs again.
    if (n_back > 0) {
      // After substeps the step ratio is 2^level; variable-step BDF2 is zero-stable only below
      // 1 + sqrt(2), so a larger jump restarts with one BDF1 step.
      for (int j = 0; j < n_padded; ++j) {
        if (j < n_active && refined_step[j] == i - 1) {
          const double w_back = sp.ds / substep_ds[j];
          back.set(j, stepTerms(sp.ds, bdf2Coefficients(w_back > 2.0 ? 0.0 : w_back), w_back));
        } else {
          back.set(j, coarse);
        }
      }
    }
    const march::StepArgs args{&constants, &strip_constants, &coarse, n_back > 0 ? &back : nullptr,
                               {x, px, sat_x}, wxa, &sums};
    advance_(args, 0, n_active, *el, next, nodes, &root_counts);
    // The packs added the coarse node solutions to `sums`. What this step adds besides, weighted by strip:
    // the change of node values by substeps (times the node's area weight wxa) and the corrections of
    // trapezoids and edge intervals (in x/a, times a b).
    Integrands node_change, corrections;
    // Substeps: per strip the smallest level L with rate h / 2^L <= resolution, within max_level and the
    // node budget (spent in strip order); 0 where the step stands.
    int n_refined = 0;
    for (int j = 0; j < n_active; ++j) {
      const double rate = nodes->refine_rate[j];
      level[j] = 0;
      if (!(rate > 0.0) || refinement_budget <= 0) continue;
      const double r = rate * h / options_.refinement.resolution;
      if (r > 1.0) level[j] = std::min(max_level, static_cast<int>(std::ceil(std::log2(r))));
      while (level[j] > 0 && (1 << level[j]) > refinement_budget) --level[j];  // never beyond the node budget
      refinement_budget -= level[j] > 0 ? 1 << level[j] : 0;
    }
    // Redo the step of strips [j0, j1) (one level L) in 2^L equal substeps ending on the node, in packs as the
    // coarse step; integrate their outputs over the substeps by the trapezoid rule and add the difference to
    // their coarse trapezoids, and replace their coarse node values in the node sums.
    auto redoInSubsteps = [&](int j0, int j1, int level_of_run) {
      const int k_sub = 1 << level_of_run;
      const double dss = sp.ds / k_sub, hds = 0.5 * sp.ds, x_i = a * xg.s[i];
      // A pack that runs past j1 also writes the lanes of the strips after the run: set them aside.
      const int spill_end = std::min(j1 + march::kMaxLanes - 1, n_padded);
      march::LaneCopy spill[march::kMaxLanes - 1];
      for (int j = j1; j < spill_end; ++j) march::saveLane(*next, *nodes, j, &spill[j - j1]);
      // The first substep's BDF2 coefficients follow each strip's last step (coarse, or substeps); the
      // lanes past the run get any valid terms.
      const march::StepTerms inner = stepTerms(dss, bdf2Coefficients(1.0), 1.0);
      for (int j = j0; j < j1; ++j) {
        const double last_ds = refined_step[j] == i - 1 ? substep_ds[j] : (i > 0 ? xg.steps[i - 1].ds : 0.0);
        const double w_in = last_ds > 0.0 ? dss / last_ds : 0.0;
        back.set(j, stepTerms(dss, bdf2Coefficients(w_in), w_in));
      }
      for (int j = j1; j < spill_end; ++j) back.set(j, inner);
      for (int j = j0; j < j1; ++j)
        node_change.add(-strip_constants.weight[j], integrands(nodeOf(*nodes, j), x, strip_constants.y_mz[j]));
      const int fine = 1 << max_level, stride = fine >> level_of_run;  // substep k is the finest grid's k stride
      for (int k = 1; k <= k_sub; ++k) {
        const double s_k = xg.s[i] - k * dss;  // substep node x/a (k * dss = k stride ds/fine exactly)
        double sat_k = sat_x, px_k = px, x_k = x;
        if (k < k_sub) {
          const size_t sub = static_cast<size_t>(i) * (fine - 1) + (k * stride - 1);
          px_k = pressureFrom(xg.sub_gx_even[sub], xg.sub_sat_gx[sub], s_k, shift_saturation_(Bx * s_k, shift_terms),
                              &sat_k);
          x_k = a * s_k;
        }
        const march::StepArgs substep{&constants, &strip_constants, &inner, k == 1 ? &back : nullptr,
                                      {x_k, px_k, sat_k}, 0.0, nullptr};
        advance_(substep, j0, j1 - j0, k == 1 ? *el : *next, next, nodes, &root_counts);
        const double c = k < k_sub ? dss : 0.5 * dss;  // trapezoid weight of substep node k
        for (int j = j0; j < j1; ++j) {
          const NodeSolution o = nodeOf(*nodes, j);
          const double w = strip_constants.weight[j];
          corrections.add(w * c, integrands(o, x_k, strip_constants.y_mz[j]));
          // The sliding wear next to an edge of the patch (see the coarse case below), on the substep there.
          if ((i == 0 && k == 1) || (i == n - 1 && k == k_sub - 1))
            corrections.wear += w * edge_weight * dss * (o.wt - w4);
        }
      }
      for (int j = j0; j < j1; ++j) {
        const double w = strip_constants.weight[j], y_mz = strip_constants.y_mz[j];
        const Integrands at_i = integrands(nodeOf(*prev_nodes, j), x_i, y_mz);
        const Integrands o = integrands(nodeOf(*nodes, j), x, y_mz);
        corrections.add(w * (0.5 * dss - hds), at_i);  // node i's share of the substeps, less the coarse trapezoid
        corrections.add(-w * hds, o);
        node_change.add(w, o);
        refined_step[j] = i;
        substep_ds[j] = dss;
      }
      for (int j = j1; j < spill_end; ++j) march::restoreLane(spill[j - j1], j, next, nodes);
      n_refined += j1 - j0;
    };
    for (int j0 = 0, j1 = 0; j0 < n_active; j0 = j1) {
      for (j1 = j0 + 1; j1 < n_active && level[j1] == level[j0];) ++j1;
      if (level[j0] > 0) redoInSubsteps(j0, j1, level[j0]);
    }
    // Strips that need more than their node solution: the edge wear of the steps that stand, the fields.
    if (edge_step || fields) {
      for (int j = 0; j < n_active; ++j) {
        const NodeSolution o = nodeOf(*nodes, j);
        // p vanishes linearly at x = +-a, so the sliding wear ~ tau^w1 ~ p^w1 has an endpoint singularity
        // there: on the interval next to an edge its integral is h f/(1 + w1), not the trapezoid's h f/2.
        const double wt_inner = i == 0 ? o.wt : prev_nodes->wt[j];  // at the interval's end away from the edge
        if (edge_step && level[j] == 0)
          corrections.wear += strip_constants.weight[j] * edge_weight * sp.ds * (wt_inner - w4);
        if (fields) store(i + 1, j, o, *next);
      }
    }
    n_back = n_refined;
    std::swap(el, next);
    std::swap(prev_nodes, nodes);
    total.add(wxa, node_change);
    total.add(a * b, corrections);
  }

  for (int lane = 0; lane < march::kMaxLanes; ++lane)
    total.add(1.0, {sums.fx[lane], sums.fy[lane], sums.mz[lane], sums.wear[lane], sums.stick[lane], sums.exact[lane]});
  const double area = 4.0 * a * b;  // sum of the weights equals the area exactly
  result->fx_n = total.fx;
  result->fy_n = total.fy;
  result->mz_nm = total.mz;
  result->wear_rate_kg_per_s = total.wear;
  result->wear_rate_kg_per_m = total.wear / V;
  result->stick_fraction = total.stick / area;
  result->slide_fraction = 1.0 - result->stick_fraction;
  result->exact_stick_fraction = total.exact / area;
  result->half_length_m = a;
  result->half_width_m = b;
  result->max_root_iterations = root_counts.max_iterations;
  result->root_iterations = root_counts.total;
  result->refined_substeps = initial_budget - refinement_budget;
}

}  // namespace tread_wear
