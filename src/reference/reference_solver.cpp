#include "tread_wear/reference/reference_solver.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"
#include "tread_wear/model/quadrature.h"
#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

// State layout. CVODE 6 has no quadrature API (CVodeQuad* belongs to CVODES, which cannot be linked
// next to CVODE: both export the same symbols), so the path integrals are appended to the state
// vector. They enter the local error test exactly as quadratures with CVodeSetQuadErrCon would.
constexpr int kDx = 0, kDy = 1;    // tip deflection delta [m]
constexpr int kVsx = 2, kVsy = 3;  // sliding velocity v_s [m/s], slide mode only (0 in stick)
constexpr int kQx = 4, kQy = 5;    // integral tau_x dx, integral tau_y dx [N/m]
constexpr int kQxTauY = 6;         // integral x tau_y dx [N]
constexpr int kQWear = 7;          // integral (w_r V) dx [kg/(s m)]
constexpr int kStates = 4;         // element states (Jacobian columns)
constexpr int kSize = 8;
constexpr int kRoots = 2;  // 0: mode event, 1: |v_s| = v_m

enum class Mode { kStick, kSlide };

}  // namespace

bool ReferenceSolverOptions::validate(std::string* error) const {
  if (n_strips < 1 || n_strips > 256) return failValidation(error, "n_strips", n_strips, "in [1, 256]");
  if (!(rel_tol > 0.0 && rel_tol <= 1e-3)) return failValidation(error, "rel_tol", rel_tol, "in (0, 1e-3]");
  if (!(abs_tol_factor > 0.0 && std::isfinite(abs_tol_factor)))
    return failValidation(error, "abs_tol_factor", abs_tol_factor, "finite and > 0");
  if (!(stop_speed_mps > 0.0 && stop_speed_mps <= 1e-6))
    return failValidation(error, "stop_speed_mps", stop_speed_mps, "in (0, 1e-6]");
  if (!(start_speed_mps > 0.0 && start_speed_mps < stop_speed_mps))
    return failValidation(error, "start_speed_mps", start_speed_mps, "in (0, stop_speed_mps)");
  if (!(static_tolerance >= 0.0 && static_tolerance <= 1e-6))
    return failValidation(error, "static_tolerance", static_tolerance, "in [0, 1e-6]");
  if (lateral_map_order < 0 || lateral_map_order > 3)
    return failValidation(error, "lateral_map_order", lateral_map_order, "in [0, 3]");
  if (max_steps < 100) return failValidation(error, "max_steps", max_steps, ">= 100");
  if (max_events_per_strip < 10) return failValidation(error, "max_events_per_strip", max_events_per_strip, ">= 10");
  return true;
}

namespace {

/// Gauss-Legendre nodes and weights in y/b, mapped eta = phi(xi) with phi' = c_k (1 - xi^2)^k (k = map_order): that
/// flattens the shoulder behaviour of the strip integrals (tau^w1 with p ~ (1 - eta) at the edge makes them
/// ~ (1 - eta)^0.3, which Gauss-Legendre alone converges at ~n^-2.6) into ~(1 - xi)^(0.3 (k + 1) + k).
void shoulderMappedGaussLegendre(int n, int map_order, std::vector<double>* eta, std::vector<double>* weight) {
  gaussLegendre(n, eta, weight);
  for (int j = 0; j < n; ++j) {
    const double xi = (*eta)[j], q = 1.0 - xi * xi;
    double mapped = xi, dphi = 1.0;
    switch (map_order) {
      case 1:
        mapped = 0.5 * xi * (3.0 - xi * xi);
        dphi = 1.5 * q;
        break;
      case 2:
        mapped = xi * (15.0 - 10.0 * xi * xi + 3.0 * std::pow(xi, 4)) / 8.0;
        dphi = 15.0 / 8.0 * q * q;
        break;
      case 3:
        mapped = xi * (35.0 - 35.0 * xi * xi + 21.0 * std::pow(xi, 4) - 5.0 * std::pow(xi, 6)) / 16.0;
        dphi = 35.0 / 16.0 * q * q * q;
        break;
      default:
        break;
    }
    (*eta)[j] = mapped;
    (*weight)[j] *= dphi;
  }
}

/// Checks a fields request of n_strips strips: sized by resize(n_x, strips()), x nodes [m] strictly descending
/// within [-a, a] (a [m] the half length).
void checkFieldRequest(const PatchFields& fields, int n_strips, double a) {
  const int nfx = fields.n_x_nodes;
  if (fields.n_strips != n_strips || static_cast<int>(fields.x_m.size()) != nfx ||
      static_cast<int>(fields.state.size()) != nfx * n_strips)
    throw std::invalid_argument("fields: resize(n_x, strips()) before evaluate()");
  for (int i = 0; i < nfx; ++i) {
    const double xi = fields.x_m[i];
    if (!(xi <= a && xi >= -a) || (i > 0 && !(xi < fields.x_m[i - 1])))
      throw std::invalid_argument("fields: x_m[" + std::to_string(i) + "] = " + std::to_string(xi) +
                                  ": must be strictly descending within [-a, a]");
  }
}

}  // namespace

/// Everything one strip integration needs; the CVODE callbacks receive a pointer to it.
struct ReferenceBrushSolver::Workspace {
  // CVODE objects, created once.
  SUNContext sunctx = nullptr;
  void* cvode = nullptr;
  N_Vector y = nullptr, abstol = nullptr;
  SUNMatrix jac = nullptr;
  SUNLinearSolver linsol = nullptr;
  std::vector<double> eta, weight;      ///< Gauss-Legendre nodes/weights in y/b
  std::array<double, kStates> scale{};  ///< natural state scales, for difference quotients

  // Model constants of the current evaluation.
  SavkoorFriction friction;
  ContactPatch patch;    ///< footprint and pressure (Eqs 6-9)
  TipKinematics kin;     ///< v_r's slip terms and yaw rate (Eq 14 generalised)
  double Vr = 0, T = 0;  ///< rolling speed V_r [m/s], contact time 2a/V_r [s]
  double kx = 0, ky = 0, cx = 0, cy = 0, m = 0, mu0 = 0, p0 = 0;
  double w1 = 0, w2 = 0, w3 = 0, w4 = 0;
  double static_factor = 1.0, stop_speed = 0.0, start_speed = 0.0, v_m = 0.0;
  // Current strip.
  double y_m = 0;
  Mode mode = Mode::kStick;
  long rhs_evals = 0;
  std::string cvode_message;
  /// The current strip's integration legs and its mode history.
  struct Strip {
    std::array<double, 8> bounds{};  ///< segment ends in t [s]: 0, where p crosses p_0 (kink of sat(p), Eq 11), T
    int n_bounds = 0;
    int seg = 1;                   ///< the segment being integrated ends at bounds[seg]
    int events = 0;                ///< mode switches
    bool first_leg = true;         ///< no CVODE steps to count before the first restart
    double stick_since = 0.0;      ///< start of the current exact stick [s]
    double fast_since = 0.0;       ///< start of the current |v_s| > v_m interval [s]
    bool fast = false;             ///< |v_s| > v_m now
    double exact_stick_len = 0.0;  ///< time in exact stick [s]
    double fast_len = 0.0;         ///< time with |v_s| > v_m [s]
    int next_field = 0;            ///< next x node of the fields to record
  } strip;
  std::array<int, kRoots> direction{};  ///< CVodeSetRootDirection of the current leg

  struct Local {
    double x, p, R;    ///< position [m], pressure [Pa], static limit sat mu_0 p [Pa]
    double vrx, vry;   ///< road-sticking velocity v_r [m/s]
    double tx, ty;     ///< shear stress tau [Pa]
    double s, ex, ey;  ///< |v_s| [m/s] and its direction (slide)
    double ux, uy;     ///< element velocity u = d delta/dt [m/s]
  };

  /// Constants of the operating point: footprint and pressure (Eqs 6-9), element stiffness (Eq 13), damping and
  /// mass, v_r (Eq 14), wear law (Eqs 19, 25) and the event thresholds.
  void setOperatingPoint(const TireParams& params, const ReferenceSolverOptions& options, const OperatingPoint& op) {
    const TreadParams& tp = params.tread;
    const WearLawParams& wl = params.wear;
    patch = ContactPatch(params.footprint, op.load_n);
    ky = tp.lateralStiffness(op.load_n);
    kx = tp.longitudinalStiffness(op.load_n);
    cx = tp.c_x_pa_s_per_m;
    cy = tp.c_y_pa_s_per_m;
    m = tp.m_kg_per_m2;
    mu0 = params.friction.mu_0;
    p0 = params.friction.p_0_pa;
    w1 = wl.w1;
    w2 = wl.w2;
    w3 = wl.w3At(op.tread_temperature_c);
    w4 = wl.w4_kg_per_s_m2;
    Vr = op.rollingSpeed();
    T = 2.0 * patch.halfLength() / Vr;
    kin = op.tipKinematics(options.orientation);
    static_factor = 1.0 + options.static_tolerance;
    stop_speed = options.stop_speed_mps;
    start_speed = options.start_speed_mps;
    v_m = params.friction.v_m_mps;
  }

  /// Natural scales: slip speed, deflection (limited by friction or by the kinematics of stick over the contact
  /// time), shear stress and path integrals; the absolute tolerances follow from them.
  void setTolerances(const ReferenceSolverOptions& options) {
    const double a = patch.halfLength(), b = patch.halfWidth();
    const double p_mean = patch.load() / patch.area();
    const double slip_scale =
        std::max({std::fabs(kin.v_rx0_mps), std::fabs(kin.v_ry0_mps), std::fabs(kin.omega_rad_per_s) * (a + b), 1e-3});
    const double deflection_scale =
        std::min(friction.saturation(p_mean) * friction.params().mu_m * p_mean / kx, slip_scale * T);
    const double tau_scale = ky * deflection_scale;
    scale = {deflection_scale, deflection_scale, slip_scale, slip_scale};
    const double wear_scale = wearRate(tau_scale, slip_scale);
    const double atol_f = options.rel_tol * options.abs_tol_factor;
    double* atol = N_VGetArrayPointer(abstol);
    atol[kDx] = atol[kDy] = atol_f * deflection_scale;
    atol[kVsx] = atol[kVsy] = atol_f * slip_scale;
    atol[kQx] = atol[kQy] = atol_f * tau_scale * 2.0 * a;
    atol[kQxTauY] = atol_f * tau_scale * 2.0 * a * a;
    atol[kQWear] = atol_f * wear_scale * 2.0 * a;
    if (CVodeSVtolerances(cvode, options.rel_tol, abstol) != CV_SUCCESS)
      throw std::runtime_error("ReferenceBrushSolver: CVodeSVtolerances failed");
  }

  /// Pressure, v_r and the stress in the current mode at time t for element state yv.
  Local local(double t, const double* yv) const {
    Local l;
    l.x = patch.halfLength() - Vr * t;
    l.p = patch.pressure(l.x, y_m);
    l.R = friction.saturation(l.p) * mu0 * l.p;
    l.vrx = kin.vrx(y_m + yv[kDy]);
    l.vry = kin.vry(l.x + yv[kDx]);
    if (mode == Mode::kStick) {
      l.s = l.ex = l.ey = 0.0;
      l.ux = l.vrx;
      l.uy = l.vry;
      stickStress(l, yv, &l.tx, &l.ty);
    } else {
      l.s = std::hypot(yv[kVsx], yv[kVsy]);
      l.ex = l.s > 0.0 ? yv[kVsx] / l.s : 0.0;
      l.ey = l.s > 0.0 ? yv[kVsy] / l.s : 0.0;
      const double mup = friction.saturation(l.p) * friction.savkoor(l.s) * l.p;
      l.tx = -mup * l.ex;
      l.ty = -mup * l.ey;
      l.ux = l.vrx + yv[kVsx];
      l.uy = l.vry + yv[kVsy];
    }
    return l;
  }

  /// Stress needed to stick: k o delta + c o v_r + m dv_r/dt with u = v_r.
  void stickStress(const Local& l, const double* yv, double* tx, double* ty) const {
    const double Omega = kin.omega_rad_per_s;
    *tx = kx * yv[kDx] + cx * l.vrx + m * Omega * l.vry;
    *ty = ky * yv[kDy] + cy * l.vry + m * Omega * (Vr - l.vrx);
  }

  /// Wear rate per time and area w_r V [kg/(s m^2)] at shear stress |tau| [Pa] and sliding speed |v_s| [m/s]
  /// (Eq 19, w3 scaled by Eq 25).
  double wearRate(double tau, double s) const {
    double w = w4;
    if (s > 0.0 && tau > 0.0) w += w3 * std::pow(tau / units::kMegapascal, w1) * std::pow(s, w2);
    return w;
  }
  /// Local wear rate per time and area, w_r V [kg/(s m^2)] (Eq 19).
  double wearPerTime(const Local& l) const { return wearRate(std::hypot(l.tx, l.ty), l.s); }

  int rhs(double t, const double* yv, double* f) {
    ++rhs_evals;
    const Local l = local(t, yv);
    const double Omega = kin.omega_rad_per_s;
    f[kDx] = l.ux;
    f[kDy] = l.uy;
    if (mode == Mode::kStick) {
      f[kVsx] = f[kVsy] = 0.0;
    } else {
      // m v_s' = tau - k o delta - c o u - m dv_r/dt, dv_r/dt = (Omega u_y, Omega (V_r - u_x)).
      f[kVsx] = (l.tx - kx * yv[kDx] - cx * l.ux) / m - Omega * l.uy;
      f[kVsy] = (l.ty - ky * yv[kDy] - cy * l.uy) / m - Omega * (Vr - l.ux);
    }
    f[kQx] = Vr * l.tx;
    f[kQy] = Vr * l.ty;
    f[kQxTauY] = Vr * l.x * l.ty;
    f[kQWear] = Vr * wearPerTime(l);
    return 0;
  }

  void roots(double t, const double* yv, double* g) const {
    if (mode == Mode::kStick) {
      const Local l = local(t, yv);
      g[0] = std::hypot(l.tx, l.ty) - l.R * static_factor;
      g[1] = 1.0;
    } else {
      // Stick again once |v_s| is below the stop speed and the stick stress is inside the static
      // disc: the later of the two crossings, so the max of the two functions crosses zero.
      const Local l = local(t, yv);
      double tx, ty;
      stickStress(l, yv, &tx, &ty);
      g[0] = std::max(l.s - stop_speed, std::hypot(tx, ty) - l.R * static_factor);
      g[1] = l.s - v_m;
    }
  }

  /// The current strip's segment ends: 0, the times where p crosses p_0 (kink of sat(p), Eq 11), found on a scan
  /// and refined by bisection, and T; the integrator restarts at each.
  void findSegments() {
    constexpr int kScan = 64;
    const double a = patch.halfLength();
    auto excess = [&](double t) { return patch.pressure(a - Vr * t, y_m) - p0; };
    strip.bounds[strip.n_bounds++] = 0.0;
    double t_prev = 0.0, e_prev = excess(0.0);
    for (int k = 1; k <= kScan && strip.n_bounds < 7; ++k) {
      const double t_k = T * k / kScan, e_k = excess(t_k);
      if ((e_prev < 0.0) != (e_k < 0.0) && k < kScan) {
        double lo = t_prev, hi = t_k;
        for (int it = 0; it < 200 && hi - lo > 1e-15 * T; ++it) {
          const double mid = 0.5 * (lo + hi);
          if ((excess(mid) < 0.0) == (e_prev < 0.0))
            lo = mid;
          else
            hi = mid;
        }
        strip.bounds[strip.n_bounds++] = 0.5 * (lo + hi);
      }
      t_prev = t_k;
      e_prev = e_k;
    }
    strip.bounds[strip.n_bounds++] = T;
  }

  /// Restarts CVODE at t0 in the current mode up to the current segment's end, adding the steps of the leg that
  /// ends to *steps (CVodeReInit resets the counter; the strip's last leg is counted by integrateStrip).
  void restart(double t0, long* steps) {
    long nst = 0;
    CVodeGetNumSteps(cvode, &nst);
    if (!strip.first_leg) *steps += nst;
    strip.first_leg = false;
    if (CVodeReInit(cvode, t0, y) != CV_SUCCESS || CVodeSetStopTime(cvode, strip.bounds[strip.seg]) != CV_SUCCESS)
      throw std::runtime_error("ReferenceBrushSolver: CVodeReInit failed: " + cvode_message);
    direction = {mode == Mode::kStick ? 1 : -1, 0};
    CVodeSetRootDirection(cvode, direction.data());
  }

  /// v_s = 0 with the stick stress outside the static disc at t [s]: slip starts along -tau_st (Coulomb's
  /// set-valued law), at the start speed.
  void enterSlideFromRest(const Local& l, double t) {
    double* yv = N_VGetArrayPointer(y);
    double tx, ty;
    stickStress(l, yv, &tx, &ty);
    if (mode == Mode::kStick) strip.exact_stick_len += t - strip.stick_since;
    mode = Mode::kSlide;
    const double tau = std::hypot(tx, ty);
    yv[kVsx] = -start_speed * tx / tau;
    yv[kVsy] = -start_speed * ty / tau;
  }

  void enterStick(double t) {
    double* yv = N_VGetArrayPointer(y);
    mode = Mode::kStick;
    strip.stick_since = t;
    yv[kVsx] = yv[kVsy] = 0.0;
  }

  /// |v_s| rises above (now_fast) or falls below v_m at t [s].
  void setFast(bool now_fast, double t) {
    if (now_fast && !strip.fast) strip.fast_since = t;
    if (!now_fast && strip.fast) strip.fast_len += t - strip.fast_since;
    strip.fast = now_fast;
  }

  /// Leading edge: a relaxed element, at rest relative to the wheel (or at the road's velocity), sticks if the
  /// stress to stick is inside the static disc, else slides.
  void enterPatch(bool enter_at_road_velocity) {
    double* yv = N_VGetArrayPointer(y);
    std::fill(yv, yv + kSize, 0.0);
    mode = Mode::kStick;
    const Local l = local(0.0, yv);
    const double ux = enter_at_road_velocity ? l.vrx : 0.0;
    const double uy = enter_at_road_velocity ? l.vry : 0.0;
    const double vsx = ux - l.vrx, vsy = uy - l.vry;
    const double s = std::hypot(vsx, vsy);
    if (s > start_speed) {
      mode = Mode::kSlide;
      yv[kVsx] = vsx;
      yv[kVsy] = vsy;
      setFast(s > v_m, 0.0);
    } else if (std::hypot(l.tx, l.ty) <= l.R * static_factor) {
      enterStick(0.0);
    } else {
      enterSlideFromRest(l, 0.0);
    }
  }

  /// The mode switch at a root of g[0] at t [s]: stick -> slide, slide -> stick; restarts CVODE.
  void switchMode(double t, int max_events, long* steps) {
    if (++strip.events > max_events)
      throw std::runtime_error("ReferenceBrushSolver: more than max_events_per_strip mode switches on strip y = " +
                               std::to_string(y_m) + " m");
    if (mode == Mode::kStick) {
      // At free rolling the stick stress is exactly zero, and where the pressure vanishes (the trailing edge, or a
      // light load's unloaded edge strips) so does the static disc: the root is a touch with no direction to slip
      // in, not a switch. The element stays in stick; the restart lets CVODE set aside a root function that stays
      // zero (continuing would stop with "root found at and very near t").
      const Local l = local(t, N_VGetArrayPointer(y));
      if (std::hypot(l.tx, l.ty) > 0.0) enterSlideFromRest(l, t);
      restart(t, steps);
    } else {
      setFast(false, t);
      enterStick(t);
      restart(t, steps);
    }
  }

  /// Records the local fields of strip j at the x nodes the element has passed by t [s]; V [m/s] converts wear
  /// per time to per distance.
  void recordFields(PatchFields* fields, int j, double V, double t) {
    const double* yv = N_VGetArrayPointer(y);
    const double a = patch.halfLength();
    while (strip.next_field < fields->n_x_nodes &&
           (a - fields->x_m[strip.next_field]) / Vr <= t * (1.0 + 1e-14) + 1e-300) {
      const Local l = local(t, yv);
      const int k = fields->index(strip.next_field, j);
      fields->pressure_pa[k] = l.p;
      fields->tau_x_pa[k] = l.tx;
      fields->tau_y_pa[k] = l.ty;
      fields->v_sx_mps[k] = l.s * l.ex;
      fields->v_sy_mps[k] = l.s * l.ey;
      fields->delta_x_m[k] = yv[kDx];
      fields->delta_y_m[k] = yv[kDy];
      fields->wear_kg_per_m3[k] = wearPerTime(l) / V;
      fields->state[k] = mode == Mode::kStick ? 0 : (l.s <= v_m ? 1 : 2);
      ++strip.next_field;
    }
  }

  /// The element path of strip j (y_m set) from the leading edge (t = 0) to the trailing edge (t = T): the hybrid
  /// ODE of stick and slide (Eqs 12-18) with its path integrals (Eq 20) in the state, leg by leg between mode
  /// switches and segment ends; the times in exact stick and with |v_s| > v_m in `strip`.
  void integrateStrip(const ReferenceSolverOptions& options, PatchFields* fields, int j, double V,
                      ReferenceSolverStats* stats) {
    strip = Strip{};
    findSegments();
    enterPatch(options.enter_at_road_velocity);
    restart(0.0, &stats->steps);
    if (fields) recordFields(fields, j, V, 0.0);
    const double a = patch.halfLength();
    double t = 0.0;
    while (true) {
      double t_target = strip.bounds[strip.seg];
      if (fields && strip.next_field < fields->n_x_nodes)
        t_target = std::min(t_target, (a - fields->x_m[strip.next_field]) / Vr);
      double t_ret = t;
      const int flag = CVode(cvode, t_target, y, &t_ret, CV_NORMAL);
      if (flag < 0) {
        const double* yv = N_VGetArrayPointer(y);
        throw std::runtime_error(
            "ReferenceBrushSolver: CVODE failed on strip y = " + std::to_string(y_m) +
            " m at x = " + std::to_string(a - Vr * t_ret) + " m in " +
            (mode == Mode::kStick ? "stick" : "slide, |v_s| = " + std::to_string(std::hypot(yv[kVsx], yv[kVsy]))) +
            ": " + cvode_message);
      }
      t = t_ret;
      if (flag == CV_ROOT_RETURN) {
        std::array<int, kRoots> found{};
        CVodeGetRootInfo(cvode, found.data());
        if (found[1] != 0) setFast(found[1] > 0, t);
        if (found[0] != 0) switchMode(t, options.max_events_per_strip, &stats->steps);
      }
      if (fields) recordFields(fields, j, V, t);
      if (t >= strip.bounds[strip.seg] * (1.0 - 1e-15)) {
        if (strip.seg == strip.n_bounds - 1) break;
        ++strip.seg;
        restart(t, &stats->steps);
      }
    }
    if (mode == Mode::kStick) strip.exact_stick_len += T - strip.stick_since;
    setFast(false, T);
    long nst = 0;
    CVodeGetNumSteps(cvode, &nst);
    stats->steps += nst;
  }

  static int rhsCallback(realtype t, N_Vector y, N_Vector ydot, void* user) {
    return static_cast<Workspace*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  }
  static int rootCallback(realtype t, N_Vector y, realtype* g, void* user) {
    static_cast<Workspace*>(user)->roots(t, N_VGetArrayPointer(y), g);
    return 0;
  }
  /// Difference-quotient Jacobian over the element states only: the path integrals do not feed
  /// back, so their columns are zero and a full dense difference quotient would waste half its work.
  static int jacCallback(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* user, N_Vector tmp1, N_Vector tmp2,
                         N_Vector) {
    Workspace* ws = static_cast<Workspace*>(user);
    SUNMatZero(J);
    double* yp = N_VGetArrayPointer(tmp1);
    double* fp = N_VGetArrayPointer(tmp2);
    const double* y0 = N_VGetArrayPointer(y);
    const double* f0 = N_VGetArrayPointer(fy);
    std::copy(y0, y0 + kSize, yp);
    // Increments for v_s scale with |v_s|: the friction direction turns at a rate ~ mu p/(m |v_s|).
    const double s = std::hypot(y0[kVsx], y0[kVsy]);
    for (int j = 0; j < kStates; ++j) {
      if (ws->mode == Mode::kStick && (j == kVsx || j == kVsy)) continue;
      const double h = (j == kVsx || j == kVsy) ? 1.5e-8 * std::max(s, ws->start_speed)
                                                : 1.5e-8 * std::max(std::fabs(y0[j]), ws->scale[j]);
      yp[j] = y0[j] + h;
      if (ws->rhs(t, yp, fp) != 0) {
        yp[j] = y0[j] - h;
        if (ws->rhs(t, yp, fp) != 0) return 1;
        for (int i = 0; i < kSize; ++i) SM_ELEMENT_D(J, i, j) = (f0[i] - fp[i]) / h;
      } else {
        for (int i = 0; i < kSize; ++i) SM_ELEMENT_D(J, i, j) = (fp[i] - f0[i]) / h;
      }
      yp[j] = y0[j];
    }
    return 0;
  }
  static void errorCallback(int, const char* module, const char* function, char* msg, void* user) {
    Workspace* ws = static_cast<Workspace*>(user);
    ws->cvode_message = std::string(module) + "::" + function + ": " + msg;
  }
};

ReferenceBrushSolver::ReferenceBrushSolver(const TireParams& params, const ReferenceSolverOptions& options)
    : params_(params), options_(options), adhesion_(params), ws_(std::make_unique<Workspace>()) {
  std::string error;
  if (!params.validate(&error)) throw std::invalid_argument("invalid tire parameters: " + error);
  if (!options.validate(&error)) throw std::invalid_argument("invalid reference solver options: " + error);
  Workspace& w = *ws_;
  shoulderMappedGaussLegendre(options.n_strips, options.lateral_map_order, &w.eta, &w.weight);
  w.friction = SavkoorFriction(params.friction);
  bool ok = SUNContext_Create(nullptr, &w.sunctx) == 0;
  if (ok) w.y = N_VNew_Serial(kSize, w.sunctx);
  if (w.y) w.abstol = N_VNew_Serial(kSize, w.sunctx);
  if (w.abstol) w.jac = SUNDenseMatrix(kSize, kSize, w.sunctx);
  if (w.jac) w.linsol = SUNLinSol_Dense(w.y, w.jac, w.sunctx);
  if (w.linsol) w.cvode = CVodeCreate(CV_BDF, w.sunctx);
  if (w.cvode) {
    N_VConst(0.0, w.y);
    N_VConst(1.0, w.abstol);
    ok = CVodeInit(w.cvode, &Workspace::rhsCallback, 0.0, w.y) == CV_SUCCESS &&
         CVodeSetUserData(w.cvode, &w) == CV_SUCCESS &&
         CVodeSVtolerances(w.cvode, options.rel_tol, w.abstol) == CV_SUCCESS &&
         CVodeSetLinearSolver(w.cvode, w.linsol, w.jac) == CV_SUCCESS &&
         CVodeSetJacFn(w.cvode, &Workspace::jacCallback) == CV_SUCCESS &&
         CVodeRootInit(w.cvode, kRoots, &Workspace::rootCallback) == CV_SUCCESS &&
         CVodeSetNoInactiveRootWarn(w.cvode) == CV_SUCCESS &&
         CVodeSetMaxNumSteps(w.cvode, options.max_steps) == CV_SUCCESS &&
         CVodeSetMaxConvFails(w.cvode, 50) == CV_SUCCESS && CVodeSetMaxErrTestFails(w.cvode, 50) == CV_SUCCESS &&
         CVodeSetErrHandlerFn(w.cvode, &Workspace::errorCallback, &w) == CV_SUCCESS;
  } else {
    ok = false;
  }
  if (!ok) throw std::runtime_error("ReferenceBrushSolver: CVODE set-up failed");
}

ReferenceBrushSolver::~ReferenceBrushSolver() {
  Workspace& w = *ws_;
  if (w.cvode) CVodeFree(&w.cvode);
  if (w.linsol) SUNLinSolFree(w.linsol);
  if (w.jac) SUNMatDestroy(w.jac);
  if (w.abstol) N_VDestroy(w.abstol);
  if (w.y) N_VDestroy(w.y);
  if (w.sunctx) SUNContext_Free(&w.sunctx);
}

void ReferenceBrushSolver::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) {
  std::string error;
  if (!op.validate(&error)) throw std::invalid_argument("invalid operating point: " + error);
  if (!(op.speed_mps > 0.0)) throw std::invalid_argument("invalid operating point: speed_mps must be > 0");
  Workspace& w = *ws_;
  // Footprint and pressure (Eqs 6-9), element and wear-law constants, v_r (Eqs 13-14, 19, 25).
  w.setOperatingPoint(params_, options_, op);
  if (!(w.Vr > 0.0)) throw std::invalid_argument("invalid operating point: rolling speed must be > 0");
  w.setTolerances(options_);
  const double a = w.patch.halfLength(), b = w.patch.halfWidth();
  if (fields) checkFieldRequest(*fields, options_.n_strips, a);

  // Element paths strip by strip (Eqs 12-18) with their path integrals, summed over the strips (Eq 20).
  stats_ = ReferenceSolverStats{};
  w.rhs_evals = 0;
  double fx = 0, fy = 0, mz = 0, wear_t = 0, exact_stick_area = 0, fast_area = 0;
  const double* yv = N_VGetArrayPointer(w.y);
  for (int j = 0; j < options_.n_strips; ++j) {
    w.y_m = b * w.eta[j];
    const double dy = b * w.weight[j];
    if (fields) fields->y_m[j] = w.y_m;
    w.integrateStrip(options_, fields, j, op.speed_mps, &stats_);
    stats_.events += w.strip.events;
    stats_.max_events_strip = std::max(stats_.max_events_strip, w.strip.events);
    fx += dy * yv[kQx];
    fy += dy * yv[kQy];
    mz += dy * (yv[kQxTauY] - w.y_m * yv[kQx]);
    wear_t += dy * yv[kQWear];
    exact_stick_area += dy * w.Vr * w.strip.exact_stick_len;
    fast_area += dy * w.Vr * w.strip.fast_len;
  }
  stats_.rhs_evals = w.rhs_evals;
  // The adhesion-zone term is closed-form over the patch (model/adhesion_wear.h), the same in both solvers.
  wear_t += adhesion_.evaluate(op, w.patch, w.kin, w.Vr).wear_kg_per_m * op.speed_mps;

  const double area = w.patch.area();
  result->fx_n = fx;
  result->fy_n = fy;
  result->mz_nm = mz;
  result->wear_rate_kg_per_s = wear_t;
  result->wear_rate_kg_per_m = wear_t / op.speed_mps;
  result->stick_fraction = 1.0 - fast_area / area;
  result->slide_fraction = fast_area / area;
  result->exact_stick_fraction = exact_stick_area / area;
  result->half_length_m = a;
  result->half_width_m = b;
  result->max_root_iterations = stats_.max_events_strip;
}

}  // namespace tread_wear
