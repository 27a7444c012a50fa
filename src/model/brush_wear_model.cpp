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
      adhesion_(params),
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

int BrushWearModel::strips() const { return static_cast<int>(std::max(y_grid_.eta.size(), entry_y_grid_.eta.size())); }

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
  double p;            ///< pressure [Pa]
  double tx, ty;       ///< shear stress [Pa]
  double vsx, vsy;     ///< sliding velocity [m/s]
  double s, z;         ///< |v_s| [m/s] and ln|v_s| (0 when not sliding)
  double mup, s_dmup;  ///< mu p [Pa] and |v_s| d(mu p)/d|v_s| [Pa] at the slide root
  double wt;           ///< wear per time and area, Eq 19 [kg/(s m^2)]
  bool stuck;          ///< exact stick (v_s = 0)
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
  return {n.p[j], n.tx[j],  n.ty[j],     n.vsx[j], n.vsy[j],         n.s[j],
          n.z[j], n.mup[j], n.s_dmup[j], n.wt[j],  n.stuck[j] != 0.0};
}

/// The integrands of node solution o at x [m] on the strip with Mz lever arm y_mz [m]; stick by the paper's
/// Section 4 definition, |v_s| <= v_m [m/s].
Integrands integrandsOf(const NodeSolution& o, double x, double y_mz, double v_m) {
  return Integrands{o.tx, o.ty, x * o.ty - y_mz * o.tx, o.wt, o.s <= v_m ? 1.0 : 0.0, o.stuck ? 1.0 : 0.0};
}

}  // namespace

/// One evaluation's element march from the leading edge x = +a to the trailing edge x = -a, all strips side by
/// side (Eqs 12-18), with the running sums of Eq 20: the operating point's constants, the per-strip state of the
/// marcher (march::PathState, march::NodeLanes) and the bookkeeping of the local substeps. It lives on
/// evaluate()'s stack (about 140 KB with GridSpec::kMaxStrips strips), so an evaluation allocates nothing.
/// Its members are defined `inline`: the library is position-independent code, in which GCC does not inline a
/// function of external linkage (another definition could interpose it), and the per-step helpers must fold into
/// the x step, and the x step into evaluate()'s loop, as before the split (callgrind: up to 20% more instructions
/// outside the SIMD kernel when they were calls).
class BrushWearModel::Sweep {
 public:
  /// @param patch footprint and pressure of the operating point (Eqs 6-9); it and the grids xg, yg (the
  ///   entry-transient ones or not) outlive the sweep
  /// @param kinematics, rolling_speed_mps v_r's terms and V_r [m/s] of op (evaluate() has them from one sincos)
  /// @param fields optional local fields, pre-sized (evaluate())
  Sweep(const BrushWearModel& model, const OperatingPoint& op, const ContactPatch& patch,
        const TipKinematics& kinematics, double rolling_speed_mps, const XGrid& xg, const YGrid& yg,
        PatchFields* fields);

  int steps() const { return n_; }
  /// Node 0 at x = +a, where p = 0 and no friction acts: the elements' entry state (model spec, "Leading edge").
  void leadingEdge();
  /// x step i, from node i to node i + 1, of every strip: one implicit BDF2 step with return mapping, then
  /// local substeps where the step ended in poorly damped sliding, then the step's terms of Eq 20.
  [[gnu::always_inline]] void step(int i);
  /// Fx, Fy, Mz, the wear rates and the area fractions (Eq 20).
  void results(WearResult* result) const;

 private:
  static constexpr int kNodeChunk = 64;  ///< nodes whose pressure is computed together (pressureAtNode)

  march::Constants marchConstants(const OperatingPoint& op) const;
  void initStrips(bool enter_at_road_velocity);
  march::StepTerms stepTerms(double ds, const march::Bdf2& c, double w) const;
  double pressureFrom(double gx_even, double sat_gx, double s, double shift, double* sat_x) const;
  double pressureAtNode(int i, double* sat_x);
  void setReturningStepTerms(int i, const march::StepTerms& coarse);
  void chooseSubstepLevels(double h);
  void redoInSubsteps(int i, int j0, int j1, const march::Node& node, Integrands* node_change, Integrands* corrections);
  void setFirstSubstepTerms(int i, int j0, int j1, int lanes_end, double dss, const march::StepTerms& inner);
  void marchSubsteps(int i, int j0, int j1, double dss, const march::StepTerms& inner, const march::Node& node,
                     Integrands* corrections);
  void addEdgeWear(int i, Integrands* corrections) const;
  void storeNode(int i, int j, const NodeSolution& o, const march::PathState& state) const;

  const BrushWearModel& model_;
  const ContactPatch& patch_;
  const XGrid& xg_;
  const YGrid& yg_;
  PatchFields* const fields_;
  const double v_mps_;       ///< V, speed of the wheel centre [m/s]
  const double vr_mps_;      ///< V_r, rolling speed: elements cross the patch at it [m/s]
  const TipKinematics kin_;  ///< v_r's slip terms and yaw rate (Eq 14 generalised)
  const double a_m_, b_m_;   ///< half length a and half width b of the patch (Eq 6) [m]
  // Pressure p = p_scale g_x g_y (Eqs 7-8) and sat(p) (Eq 11) at the nodes: the grids hold g_x's even part and
  // its power -q; the centre shift's factors (1 - B s) and (1 - B s)^-q and the scales depend on Fz.
  const double bx_;           ///< B of g_x (Eq 7) [-]
  const double p_scale_pa_;   ///< Fz/(2a)/(2b) [Pa]
  const double sat_scale_;    ///< (p_scale/p_ref)^-q [-]
  const int shift_terms_;     ///< series terms of (1 - B s)^-q for |B s| <= |B| (ShiftSaturation)
  const int n_;               ///< x steps
  const int ny_;              ///< strips of the grid
  const bool mirror_;         ///< march half the strips: v_r does not depend on y without turn slip, g_y is even
  const int n_active_;        ///< strips marched
  const int n_padded_;        ///< strips with lanes: the packs may run up to kMaxLanes past n_active_
  const int max_level_;       ///< finest substep level (2^max_level substeps per step)
  const int initial_budget_;  ///< substep nodes allowed in this evaluation
  const double edge_weight_;  ///< 1/(1 + w1) - 1/2: the edge intervals' wear weight over the trapezoid's [-]
  const march::Constants constants_;  ///< the march's scalars, from the members above (marchConstants)
  int refinement_budget_;             ///< substep nodes left
  march::StripConstants strips_;
  // Two path states, at node i and at node i + 1, swapped after each x step: a step redone in substeps starts
  // again from node i without a copy. The same for the node solutions, those at node i being the start of the
  // trapezoid correction of a step redone in substeps.
  march::PathState paths_[2];
  march::PathState* el_ = &paths_[0];
  march::PathState* next_ = &paths_[1];
  march::NodeLanes node_buffers_[2];
  march::NodeLanes* prev_nodes_ = &node_buffers_[0];
  march::NodeLanes* nodes_ = &node_buffers_[1];
  int refined_step_[GridSpec::kMaxStrips];   ///< per strip the last step redone in substeps (-2: none)
  double substep_ds_[GridSpec::kMaxStrips];  ///< per strip the substep length of that step [x/a]
  int level_[GridSpec::kMaxStrips];          ///< per strip 2^level substeps in the current step, 0 where it stands
  int n_back_ = 0;                           ///< strips redone in substeps in the previous step
  march::StepTermLanes back_;                ///< per x step: step terms of strips coming back from substeps
  march::PatchSums sums_{};                  ///< the packs' sums of the coarse node solutions
  march::RootCounts root_counts_;
  Integrands total_;  ///< everything else of Eq 20 and the stick areas: N, N m, kg/s, m^2
  double chunk_px_[kNodeChunk], chunk_sat_[kNodeChunk];  ///< pressureAtNode's p/g_y [Pa] and sat_x [-]
  int chunk_first_ = -kNodeChunk;                        ///< their first node
};

inline BrushWearModel::Sweep::Sweep(const BrushWearModel& model, const OperatingPoint& op, const ContactPatch& patch,
                                    const TipKinematics& kinematics, double rolling_speed_mps, const XGrid& xg,
                                    const YGrid& yg, PatchFields* fields)
    : model_(model),
      patch_(patch),
      xg_(xg),
      yg_(yg),
      fields_(fields),
      v_mps_(op.speed_mps),
      vr_mps_(rolling_speed_mps),
      kin_(kinematics),
      a_m_(patch.halfLength()),
      b_m_(patch.halfWidth()),
      bx_(patch.shapeX().B()),
      p_scale_pa_(patch.pressureScale()),
      sat_scale_(std::pow(p_scale_pa_ / model.params_.friction.p_ref_pa, -model.params_.friction.q)),
      shift_terms_(model.shift_saturation_.terms(std::fabs(bx_))),
      n_(static_cast<int>(xg.s.size()) - 1),
      ny_(static_cast<int>(yg.eta.size())),
      mirror_(model.options_.use_symmetry && yg.symmetric && kin_.omega_rad_per_s == 0.0),
      n_active_(mirror_ ? (ny_ + 1) / 2 : ny_),
      n_padded_(std::min(n_active_ + march::kMaxLanes, march::kCapacity)),
      max_level_(model.options_.refinement.max_level),
      initial_budget_(max_level_ > 0 ? model.options_.refinement.node_budget : 0),
      edge_weight_(1.0 / (1.0 + model.params_.wear.w1) - 0.5),
      constants_(marchConstants(op)),
      refinement_budget_(initial_budget_) {
  initStrips(model.options_.enter_at_road_velocity);
  if (fields_) {
    for (int i = 0; i <= n_; ++i) fields_->x_m[i] = a_m_ * xg_.s[i];
    fields_->n_strips = ny_;
    for (int j = 0; j < ny_; ++j) fields_->y_m[j] = b_m_ * yg_.eta[j];
  }
}

inline march::Constants BrushWearModel::Sweep::marchConstants(const OperatingPoint& op) const {
  const FrictionParams& fr = model_.params_.friction;
  const TreadParams& tp = model_.params_.tread;
  const WearLawParams& wl = model_.params_.wear;
  const BrushOptions& options = model_.options_;
  march::Constants k;
  k.vrx0 = kin_.v_rx0_mps;
  k.vry0 = kin_.v_ry0_mps;
  k.omega = kin_.omega_rad_per_s;
  k.kx = tp.longitudinalStiffness(op.load_n);
  k.ky = tp.lateralStiffness(op.load_n);
  k.m = tp.m_kg_per_m2;
  k.cx = tp.c_x_pa_s_per_m;
  k.cy = tp.c_y_pa_s_per_m;
  // Friction, Eqs 10-11, in l = ln(|v_s|/v_m).
  k.p_0 = fr.p_0_pa;
  k.sat_floor = model_.friction_.saturation(fr.p_0_pa);
  k.mu_0 = fr.mu_0;
  k.dmu = fr.mu_m - fr.mu_0;
  k.savkoor_c = model_.friction_.savkoorC();
  k.ln_vm = std::log(fr.v_m_mps);
  k.z_floor = std::log(options.creep_floor_mps);
  k.savkoor_floor = model_.friction_.savkoor(options.creep_floor_mps);
  k.v_m = fr.v_m_mps;
  k.tol = options.root_tolerance;
  k.max_iterations = options.max_root_iterations;
  k.passes = kin_.omega_rad_per_s == 0.0 ? 1 : options.turn_slip_iterations;
  // Wear law, Eq 19 with Eq 25, in logarithms: ln(w3 (|tau|/1 MPa)^w1 |v_s|^w2).
  k.w1 = wl.w1;
  k.w2 = wl.w2;
  k.w4 = wl.w4_kg_per_s_m2;
  k.ln_w3_over_mpa_w1 = std::log(wl.w3At(op.tread_temperature_c)) - wl.w1 * std::log(units::kMegapascal);
  // ln|v_s| below which w3 (|tau|/1 MPa)^w1 |v_s|^w2 < 1e-9 w4 for any |tau| <= 100 MPa.
  k.z_wear_cut = k.w4 > 0.0 ? (std::log(1e-9 * k.w4) - k.ln_w3_over_mpa_w1 - k.w1 * std::log(100e6)) / k.w2
                            : -std::numeric_limits<double>::infinity();
  k.refine = initial_budget_ > 0;
  k.damping_ratio = options.refinement.damping_ratio;
  return k;
}

inline void BrushWearModel::Sweep::initStrips(bool enter_at_road_velocity) {
  for (int j = 0; j < n_padded_; ++j) {  // the strips from n_active_ on are zero and never read back
    const bool active = j < n_active_;
    const double mirror_factor = (mirror_ && 2 * j + 1 != ny_) ? 2.0 : 1.0;  // a mirrored pair counts twice
    strips_.weight[j] = active ? yg_.wy[j] * mirror_factor : 0.0;
    strips_.y_mz[j] = active && !mirror_ ? b_m_ * yg_.eta[j] : 0.0;
    strips_.y[j] = active ? b_m_ * yg_.eta[j] : 0.0;
    strips_.gy[j] = active ? yg_.gy[j] : 0.0;
    strips_.sat_y[j] = active ? yg_.sat_y[j] : 0.0;
    // Entry state: relaxed, at rest relative to the wheel, or with the road's velocity u = v_r.
    for (auto field : march::kStateFields) (el_->*field)[j] = 0.0;
    const bool at_road = active && enter_at_road_velocity;
    el_->ux[j] = at_road ? kin_.v_rx0_mps + kin_.omega_rad_per_s * b_m_ * yg_.eta[j] : 0.0;
    el_->uy[j] = at_road ? kin_.vry(a_m_) : 0.0;
  }
  for (int j = 0; j < n_active_; ++j) refined_step_[j] = -2;  // none
}

inline march::StepTerms BrushWearModel::Sweep::stepTerms(double ds, const march::Bdf2& c, double w) const {
  march::StepTerms t;
  t.c = c;
  t.w = w;
  t.g = c.beta * a_m_ * ds / vr_mps_;
  t.m_over_g = constants_.m / t.g;
  t.dx = t.m_over_g + constants_.cx + constants_.kx * t.g;
  t.dy = t.m_over_g + constants_.cy + constants_.ky * t.g;
  t.inv_dx = 1.0 / t.dx;
  t.inv_dy = 1.0 / t.dy;
  return t;
}

/// p / g_y [Pa] and the x factor of sat(p) at x/a = s from the grid's g_x even part and its power -q there and the
/// shift factor (1 - B s)^-q: (p/p_ref)^-q separates into this evaluation's scale and those factors (no pow).
inline double BrushWearModel::Sweep::pressureFrom(double gx_even, double sat_gx, double s, double shift,
                                                  double* sat_x) const {
  const double px = std::max(0.0, p_scale_pa_ * gx_even * (1.0 - bx_ * s));
  *sat_x = px > 0.0 ? sat_scale_ * sat_gx * shift : 0.0;
  return px;
}

/// pressureFrom at grid node i, computed for a chunk of nodes at a time, so that the independent series of the
/// shift factor overlap instead of each waiting in the x step's chain.
inline double BrushWearModel::Sweep::pressureAtNode(int i, double* sat_x) {
  if (i >= chunk_first_ + kNodeChunk) {
    chunk_first_ = i;
    const int count = std::min(kNodeChunk, n_ + 1 - i);
    double shift_u[kNodeChunk], shift[kNodeChunk];
    for (int k = 0; k < count; ++k) shift_u[k] = bx_ * xg_.s[i + k];
    model_.shift_saturation_(shift_u, count, shift_terms_, shift);
    for (int k = 0; k < count; ++k)
      chunk_px_[k] = pressureFrom(xg_.gx_even[i + k], xg_.sat_gx[i + k], xg_.s[i + k], shift[k], &chunk_sat_[k]);
  }
  *sat_x = chunk_sat_[i - chunk_first_];
  return chunk_px_[i - chunk_first_];
}

inline void BrushWearModel::Sweep::leadingEdge() {
  const double w0 = xg_.wx[0] * a_m_ * b_m_;
  march::NodeLanes& o = *prev_nodes_;
  for (int j = 0; j < n_active_; ++j) {  // no friction: the element slips at u - v_r
    const double vsx = el_->ux[j] - kin_.vrx(b_m_ * yg_.eta[j]), vsy = el_->uy[j] - kin_.vry(a_m_);
    const double vs = std::sqrt(vsx * vsx + vsy * vsy);
    o.p[j] = o.tx[j] = o.ty[j] = o.z[j] = o.mup[j] = o.s_dmup[j] = o.refine_rate[j] = 0.0;
    o.vsx[j] = vsx;
    o.vsy[j] = vsy;
    o.s[j] = vs;
    o.wt[j] = constants_.w4;
    o.stuck[j] = vs == 0.0 ? 1.0 : 0.0;
    total_.add(w0 * strips_.weight[j], integrandsOf(nodeOf(o, j), a_m_, strips_.y_mz[j], constants_.v_m));
    if (fields_) storeNode(0, j, nodeOf(o, j), *el_);
  }
}

inline void BrushWearModel::Sweep::step(int i) {
  const Step& sp = xg_.steps[i];
  const march::StepTerms coarse = stepTerms(sp.ds, march::Bdf2{sp.a1, sp.a2, sp.beta}, sp.w);
  march::Node node;
  node.x = a_m_ * xg_.s[i + 1];
  node.px = pressureAtNode(i + 1, &node.sat_x);
  const double wxa = xg_.wx[i + 1] * a_m_ * b_m_;
  // All strips advance to node i + 1 together; then runs of neighbouring strips that need the same number of
  // substeps redo the step together, in packs again.
  if (n_back_ > 0) setReturningStepTerms(i, coarse);
  const march::StepArgs args{&constants_, &strips_, &coarse, n_back_ > 0 ? &back_ : nullptr, node, wxa, &sums_};
  model_.advance_(args, 0, n_active_, *el_, next_, nodes_, &root_counts_);
  // The packs added the coarse node solutions to sums_. What this step adds besides, weighted by strip: the
  // change of node values by substeps (times the node's area weight wxa) and the corrections of trapezoids and
  // edge intervals (in x/a, times a b).
  Integrands node_change, corrections;
  chooseSubstepLevels(a_m_ * sp.ds / vr_mps_);
  int n_refined = 0;
  for (int j0 = 0, j1 = 0; j0 < n_active_; j0 = j1) {
    for (j1 = j0 + 1; j1 < n_active_ && level_[j1] == level_[j0];) ++j1;
    if (level_[j0] == 0) continue;
    redoInSubsteps(i, j0, j1, node, &node_change, &corrections);
    n_refined += j1 - j0;
  }
  if (i == 0 || i == n_ - 1) addEdgeWear(i, &corrections);
  if (fields_)
    for (int j = 0; j < n_active_; ++j) storeNode(i + 1, j, nodeOf(*nodes_, j), *next_);
  n_back_ = n_refined;
  std::swap(el_, next_);
  std::swap(prev_nodes_, nodes_);
  total_.add(wxa, node_change);
  total_.add(a_m_ * b_m_, corrections);
}

/// The step terms of x step i per strip, for the strips coming back from substeps in step i - 1: after substeps
/// the step ratio is 2^level; variable-step BDF2 is zero-stable only below 1 + sqrt(2), so a larger jump
/// restarts with one BDF1 step.
inline void BrushWearModel::Sweep::setReturningStepTerms(int i, const march::StepTerms& coarse) {
  const double ds = xg_.steps[i].ds;
  for (int j = 0; j < n_padded_; ++j) {
    if (j < n_active_ && refined_step_[j] == i - 1) {
      const double w_back = ds / substep_ds_[j];
      back_.set(j, stepTerms(ds, bdf2Coefficients(w_back > 2.0 ? 0.0 : w_back), w_back));
    } else {
      back_.set(j, coarse);
    }
  }
}

/// Per strip the smallest level L with rate h / 2^L <= resolution for the step's duration h [s], within
/// max_level and the node budget (spent in strip order); 0 where the step stands.
inline void BrushWearModel::Sweep::chooseSubstepLevels(double h) {
  for (int j = 0; j < n_active_; ++j) {
    const double rate = nodes_->refine_rate[j];
    level_[j] = 0;
    if (!(rate > 0.0) || refinement_budget_ <= 0) continue;
    const double r = rate * h / model_.options_.refinement.resolution;
    if (r > 1.0) level_[j] = std::min(max_level_, static_cast<int>(std::ceil(std::log2(r))));
    while (level_[j] > 0 && (1 << level_[j]) > refinement_budget_) --level_[j];  // never beyond the node budget
    refinement_budget_ -= level_[j] > 0 ? 1 << level_[j] : 0;
  }
}

/// Redoes x step i of strips [j0, j1) (one level L) in 2^L equal substeps ending on the coarse `node`, in packs
/// as the coarse step; integrates their outputs over the substeps by the trapezoid rule, adds the difference to
/// their coarse trapezoids, and replaces their coarse node values in the node sums.
inline void BrushWearModel::Sweep::redoInSubsteps(int i, int j0, int j1, const march::Node& node,
                                                  Integrands* node_change, Integrands* corrections) {
  const double v_m = constants_.v_m;
  const double ds = xg_.steps[i].ds;
  const double dss = ds / (1 << level_[j0]), hds = 0.5 * ds, x_i = a_m_ * xg_.s[i];
  // A pack that runs past j1 also writes the lanes of the strips after the run: set them aside.
  const int spill_end = std::min(j1 + march::kMaxLanes - 1, n_padded_);
  march::LaneCopy spill[march::kMaxLanes - 1];
  for (int j = j1; j < spill_end; ++j) march::saveLane(*next_, *nodes_, j, &spill[j - j1]);
  const march::StepTerms inner = stepTerms(dss, bdf2Coefficients(1.0), 1.0);
  setFirstSubstepTerms(i, j0, j1, spill_end, dss, inner);
  for (int j = j0; j < j1; ++j)
    node_change->add(-strips_.weight[j], integrandsOf(nodeOf(*nodes_, j), node.x, strips_.y_mz[j], v_m));
  marchSubsteps(i, j0, j1, dss, inner, node, corrections);
  for (int j = j0; j < j1; ++j) {
    const double w = strips_.weight[j], y_mz = strips_.y_mz[j];
    const Integrands at_i = integrandsOf(nodeOf(*prev_nodes_, j), x_i, y_mz, v_m);
    const Integrands o = integrandsOf(nodeOf(*nodes_, j), node.x, y_mz, v_m);
    corrections->add(w * (0.5 * dss - hds), at_i);  // node i's share of the substeps, less the coarse trapezoid
    corrections->add(-w * hds, o);
    node_change->add(w, o);
    refined_step_[j] = i;
    substep_ds_[j] = dss;
  }
  for (int j = j1; j < spill_end; ++j) march::restoreLane(spill[j - j1], j, next_, nodes_);
}

/// The first substep's BDF2 coefficients follow each strip's last step (coarse, or substeps); the lanes past the
/// run, up to lanes_end, get any valid terms (`inner`).
inline void BrushWearModel::Sweep::setFirstSubstepTerms(int i, int j0, int j1, int lanes_end, double dss,
                                                        const march::StepTerms& inner) {
  for (int j = j0; j < j1; ++j) {
    const double last_ds = refined_step_[j] == i - 1 ? substep_ds_[j] : (i > 0 ? xg_.steps[i - 1].ds : 0.0);
    const double w_in = last_ds > 0.0 ? dss / last_ds : 0.0;
    back_.set(j, stepTerms(dss, bdf2Coefficients(w_in), w_in));
  }
  for (int j = j1; j < lanes_end; ++j) back_.set(j, inner);
}

/// The substeps of length dss [x/a] of strips [j0, j1) in x step i, ending on the coarse `node`, and their
/// trapezoids (Eq 20) with the endpoint weight of the sliding wear on a substep next to an edge (addEdgeWear).
inline void BrushWearModel::Sweep::marchSubsteps(int i, int j0, int j1, double dss, const march::StepTerms& inner,
                                                 const march::Node& node, Integrands* corrections) {
  const int k_sub = 1 << level_[j0];
  const int fine = 1 << max_level_, stride = fine >> level_[j0];  // substep k is the finest grid's k stride
  for (int k = 1; k <= k_sub; ++k) {
    march::Node sub = node;
    if (k < k_sub) {
      const double s_k = xg_.s[i] - k * dss;  // substep node x/a (k * dss = k stride ds/fine exactly)
      const size_t m = static_cast<size_t>(i) * (fine - 1) + (k * stride - 1);
      sub.px = pressureFrom(xg_.sub_gx_even[m], xg_.sub_sat_gx[m], s_k,
                            model_.shift_saturation_(bx_ * s_k, shift_terms_), &sub.sat_x);
      sub.x = a_m_ * s_k;
    }
    const march::StepArgs args{&constants_, &strips_, &inner, k == 1 ? &back_ : nullptr, sub, 0.0, nullptr};
    model_.advance_(args, j0, j1 - j0, k == 1 ? *el_ : *next_, next_, nodes_, &root_counts_);
    const double c = k < k_sub ? dss : 0.5 * dss;  // trapezoid weight of substep node k
    for (int j = j0; j < j1; ++j) {
      const NodeSolution o = nodeOf(*nodes_, j);
      const double w = strips_.weight[j];
      corrections->add(w * c, integrandsOf(o, sub.x, strips_.y_mz[j], constants_.v_m));
      if ((i == 0 && k == 1) || (i == n_ - 1 && k == k_sub - 1))
        corrections->wear += w * edge_weight_ * dss * (o.wt - constants_.w4);
    }
  }
}

/// p vanishes linearly at x = +-a, so the sliding wear ~ tau^w1 ~ p^w1 has an endpoint singularity there: on the
/// interval next to an edge its integral is h f/(1 + w1), not the trapezoid's h f/2. For the strips whose edge
/// step i stands (those redone in substeps got it on their substep there).
inline void BrushWearModel::Sweep::addEdgeWear(int i, Integrands* corrections) const {
  const double ds = xg_.steps[i].ds;
  for (int j = 0; j < n_active_; ++j) {
    const double wt_inner = i == 0 ? nodes_->wt[j] : prev_nodes_->wt[j];  // at the interval's end away from the edge
    if (level_[j] == 0) corrections->wear += strips_.weight[j] * edge_weight_ * ds * (wt_inner - constants_.w4);
  }
}

inline void BrushWearModel::Sweep::storeNode(int i, int j, const NodeSolution& o, const march::PathState& state) const {
  const unsigned char st = o.stuck ? 0 : (o.s <= constants_.v_m ? 1 : 2);
  for (int jj : {j, ny_ - 1 - j}) {
    const int k = fields_->index(i, jj);
    fields_->pressure_pa[k] = o.p;
    fields_->tau_x_pa[k] = o.tx;
    fields_->tau_y_pa[k] = o.ty;
    fields_->v_sx_mps[k] = o.vsx;
    fields_->v_sy_mps[k] = o.vsy;
    fields_->delta_x_m[k] = state.dlx[j];
    fields_->delta_y_m[k] = state.dly[j];
    fields_->wear_kg_per_m3[k] = o.wt / v_mps_;
    fields_->state[k] = st;
    if (!mirror_) break;
  }
}

inline void BrushWearModel::Sweep::results(WearResult* result) const {
  Integrands total = total_;
  for (int lane = 0; lane < march::kMaxLanes; ++lane)
    total.add(1.0,
              {sums_.fx[lane], sums_.fy[lane], sums_.mz[lane], sums_.wear[lane], sums_.stick[lane], sums_.exact[lane]});
  const double area = patch_.area();  // sum of the weights equals the area exactly
  result->fx_n = total.fx;
  result->fy_n = total.fy;
  result->mz_nm = total.mz;
  result->wear_rate_kg_per_s = total.wear;
  result->wear_rate_kg_per_m = total.wear / v_mps_;
  result->stick_fraction = total.stick / area;
  result->slide_fraction = 1.0 - result->stick_fraction;
  result->exact_stick_fraction = total.exact / area;
  result->half_length_m = a_m_;
  result->half_width_m = b_m_;
  result->max_root_iterations = root_counts_.max_iterations;
  result->root_iterations = root_counts_.total;
  result->refined_substeps = initial_budget_ - refinement_budget_;
}

void BrushWearModel::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) const {
  // Footprint and pressure (Eqs 6-9); the road's velocity under the tread (Eq 14) and the rolling speed.
  const ContactPatch patch(params_.footprint, op.load_n);
  const TipKinematics kinematics = op.tipKinematics(options_.orientation);
  const double rolling_speed = op.rollingSpeed();
  // The grids: the entry-transient ones where an element crosses the patch within its natural period.
  const bool entry = entryTransient(patch.halfLength(), params_.tread.longitudinalStiffness(op.load_n), rolling_speed);
  const YGrid& yg = entry && !entry_y_grid_.eta.empty() ? entry_y_grid_ : y_grid_;
  Sweep sweep(*this, op, patch, kinematics, rolling_speed, entry ? entry_x_grid_ : x_grid_, yg, fields);
  // Element march (Eqs 12-18) from the leading to the trailing edge, adding the integrands of Eq 20.
  sweep.leadingEdge();
  for (int i = 0; i < sweep.steps(); ++i) sweep.step(i);
  // Forces, aligning moment, wear rate (Eq 20) and the stick areas.
  sweep.results(result);
  // The road extension: wear by micro-slip in the adhesion zone (adhesion_wear.h; off unless the tire file sets it).
  if (!adhesion_.off()) {
    result->wear_rate_kg_per_m += adhesion_.evaluate(op, patch, kinematics, rolling_speed).wear_kg_per_m;
    result->wear_rate_kg_per_s = result->wear_rate_kg_per_m * op.speed_mps;
  }
}

}  // namespace tread_wear
