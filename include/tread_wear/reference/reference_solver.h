#pragma once
/// @file reference_solver.h
/// Reference solver of the brush wear model (paper Section 3.2, Eqs 12-18, wear Eqs 19-20 and 25):
/// the same physics, inputs and outputs as BrushWearModel (brush_wear_model.h), solved by an
/// independent scheme so that each can check the other.
///
/// Physics, per tread element (per unit area) on a lateral strip y, in time t along its path
/// x(t) = a - V_r t from the leading edge (t = 0) to the trailing edge (t = T = 2a/V_r):
///   m u' = tau - k o delta - c o u,  delta' = u            (Eqs 12, 17; k = (phi k_y, k_y), Eq 13)
///   v_r(t, delta) = (kappa V_x + Omega (y + delta_y), -V sin(alpha) - Omega (x(t) + delta_x))
///                                                          (Eq 14 generalised, operating_point.h)
///   v_s = u - v_r                                          (Eq 16)
///   tau = -mu(|v_s|, p) p v_s/|v_s| while sliding          (Eqs 10-11, 18 with friction opposing slip)
///   w_r V = w4 + w3 (|tau|/1 MPa)^w1 (|v_s|/1 m/s)^w2       (Eq 19; w3 scaled by Eq 25 if enabled)
/// Fx, Fy = integral tau dA, Mz = integral (x tau_y - y tau_x) dA, W_r = integral w_r dA (Eq 20).
///
/// Scheme (what differs from the marcher):
/// - Stick and slide are modes of a hybrid ODE, switched by CVODE root finding (CVodeRootInit):
///   * stick: state delta (2), delta' = v_r(t, delta), u = v_r; the stress needed to stick is
///     tau_st = k o delta + c o v_r + m dv_r/dt with dv_r/dt = (Omega v_ry, Omega (V_r - v_rx)).
///     Event: |tau_st| = sat(p) mu_0 p (1 + eps_static) -> slide, starting along -tau_st.
///   * slide: states delta (2) and the sliding velocity v_s (2) itself, not u = v_r + v_s: in the
///     creep regime |v_s| ~ 1e-8 m/s and below (p dmu/dv_s / m reaches 1e8..1e10 1/s) would be lost in
///     the rounding of u ~ V sin(alpha); with v_s as the state, the absolute tolerance on v_s
///     (rel_tol * abs_tol_factor * slip scale, ~1e-13 m/s) resolves it:
///       m v_s' = tau - k o delta - c o u - m dv_r/dt,  dv_r/dt = (Omega u_y, Omega (V_r - u_x)).
///     The friction direction is discontinuous at v_s = 0; the integrator never crosses it: the
///     event max(|v_s| - v_stop, |tau_st| - sat(p) mu_0 p (1 + eps_static)) = 0 (both below zero:
///     slow enough and the stick stress inside the static disc) switches back to stick. v_stop =
///     1e-8 m/s costs nothing: an element decelerating at Delta/m covers m v_stop^2/(2 Delta) ~ 1e-16 m
///     more, and a creeping element above the static limit stays in slide whatever its |v_s|.
///   * extra event: |v_s| = v_m (Section 4 stick/slide boundary, for the area fraction). The points
///     where p crosses p_0 (kink of sat(p), Eq 11) are found per strip beforehand (bisection); the
///     integrator stops and restarts there.
///   CVODE: BDF, dense linear solver, Jacobian by difference quotients over the element states (the
///   v_s increments scale with |v_s|, where the friction direction turns), vector absolute
///   tolerances scaled to each state's natural size, restarted (CVodeReInit) at every mode switch.
///   eps_static = 1e-8 keeps the two events consistent: creep with |v_s| below ~3e-12 m/s (stress
///   within 1e-8 of the static limit) counts as stick.
/// - Forces, Mz and wear are path integrals (dx = V_r dt) integrated by CVODE as extra states inside
///   the same error control, so x is integrated as accurately as the element states. (CVODE 6 has no
///   quadrature API; CVodeQuad* is CVODES, which cannot be linked next to CVODE. Appending the
///   integrals to the state is what CVodeSetQuadErrCon would do; the Jacobian skips their zero columns.)
///   Exact-stick and |v_s| > v_m lengths come from the event times.
/// - Lateral integration by Gauss-Legendre in y/b (n_strips nodes), independent of the marcher's
///   sine-clustered midpoint strips; the nodes cluster at the shoulders where g_y drops steeply.
/// The marcher instead uses fixed-step BDF2 on a graded x grid with a return mapping per step,
/// trapezoid sums in x and midpoint strips in y.
///
/// Assumptions and limits: as BrushWearModel (steady state, rigid carcass, flat rectangular
/// footprint, no camber, fictitious forces of the yawing frame neglected); speed > 0. A strip
/// integration that fails (CVODE error or too many mode switches) throws std::runtime_error.
/// evaluate() is not const and not thread-safe: the solver owns its CVODE workspace, allocated once
/// in the constructor; evaluate() allocates nothing. Typical cost: tens of ms per evaluation
/// (docs/convergence.md), so this is for checks and studies, not the real-time node.

#include <memory>
#include <string>

#include "tread_wear/model/adhesion_wear.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/operating_point.h"
#include "tread_wear/model/tire_params.h"

namespace tread_wear {

struct ReferenceSolverOptions {
  int n_strips = 24;                 ///< Gauss-Legendre nodes across the width [-], 1..256
  int lateral_map_order = 1;         ///< k of the shoulder map eta = phi(xi), phi' ~ (1 - xi^2)^k [-], 0..3
  double rel_tol = 1e-8;             ///< CVODE relative tolerance (states and quadratures) [-], (0, 1e-3]
  double abs_tol_factor = 1e-3;      ///< absolute tolerance = rel_tol * factor * natural scale [-], > 0
  double stop_speed_mps = 1e-8;      ///< below this |v_s| a slider may stick again [m/s], (0, 1e-6]
  double start_speed_mps = 1e-12;    ///< |v_s| with which slip starts from stick [m/s], < stop speed
  double static_tolerance = 1e-8;    ///< eps_static, relative slack of the static disc [-], [0, 1e-6]
  long max_steps = 500000;           ///< CVODE steps allowed per integration leg [-], >= 100
  int max_events_per_strip = 10000;  ///< mode switches and restarts allowed per strip [-], >= 10
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  bool enter_at_road_velocity = false;  ///< leading-edge alternative of the model spec (u = v_r)

  /// Names the first invalid field, its value and the broken constraint.
  bool validate(std::string* error) const;
};

/// Counters of the last evaluation (for the convergence study and for tests).
struct ReferenceSolverStats {
  long steps = 0;            ///< CVODE steps over all strips
  long rhs_evals = 0;        ///< right-hand-side evaluations (including Jacobian difference quotients)
  int events = 0;            ///< mode switches and restarts over all strips
  int max_events_strip = 0;  ///< worst strip
};

/// The brush wear model solved per strip by CVODE with stick/slide events (see the file comment).
class ReferenceBrushSolver {
 public:
  /// @throw std::invalid_argument naming the field when params or options are invalid.
  ReferenceBrushSolver(const TireParams& params, const ReferenceSolverOptions& options);
  ~ReferenceBrushSolver();
  ReferenceBrushSolver(const ReferenceBrushSolver&) = delete;
  ReferenceBrushSolver& operator=(const ReferenceBrushSolver&) = delete;

  /// Evaluates one steady operating point (must satisfy OperatingPoint::validate(), speed > 0).
  /// @param[in] op operating point
  /// @param[out] result global outputs (max_root_iterations holds the worst events per strip)
  /// @param[in,out] fields optional local fields: size it with fields->resize(n_x, strips()) and set
  ///   fields->x_m to the requested x nodes [m], descending within [-a, a] (a from
  ///   params().footprint.halfLength(op.load_n)); the solver fills y_m (the Gauss nodes) and the fields.
  /// @throw std::invalid_argument for an invalid point or fields request, std::runtime_error if CVODE fails.
  void evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields = nullptr);

  int strips() const { return options_.n_strips; }
  const TireParams& params() const { return params_; }
  const ReferenceSolverOptions& options() const { return options_; }
  const ReferenceSolverStats& lastStats() const { return stats_; }

 private:
  struct Workspace;  ///< CVODE memory, vectors and the per-strip context
  TireParams params_;
  ReferenceSolverOptions options_;
  AdhesionWear adhesion_;
  ReferenceSolverStats stats_;
  std::unique_ptr<Workspace> ws_;
};

}  // namespace tread_wear
