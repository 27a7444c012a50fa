#pragma once
/// @file brush_wear_model.h
/// Brush model of massed Kelvin-Voigt tread elements with stick and slide (paper Section 3.2,
/// Eqs 12-18) and the generalized-friction-power wear law integrated over the patch (Section 3.3,
/// Eqs 19-20, temperature variant Eq 25). Implemented to the project's model spec.
///
/// Physics, per tread element (per unit area) on a lateral strip y, from the leading edge x = +a
/// to the trailing edge x = -a at the rolling speed V_r:
///   m u' = tau - k o delta - c o u,  u = d delta/dt        (Eqs 12, 17; k = (phi k_y, k_y), Eq 13)
///   k_y = k_y0 + k_y1 Fz                                   (Eq 13)
///   v_s = u - v_r (operating_point.h)                      (Eq 16)
///   stick (v_s = 0) while |k delta + c v_r + m dv_r/dt| <= sat(p) mu_0 p, else
///   slide with tau = -mu(|v_s|, p) p v_s/|v_s|            (Eqs 10, 18 with friction opposing slip)
///   w_r = (w4 + w3 (|tau|/1 MPa)^w1 (|v_s|/1 m/s)^w2) / V  (Eq 19, per unit area and distance)
///   W_r = integral w_r dA,  Fx, Fy = integral tau dA,  Mz = integral (x tau_y - y tau_x) dA  (Eq 20)
///   plus, where the tire file sets its coefficient, the adhesion zone's micro-slip wear (adhesion_wear.h; not in
///   the paper: the road extension; it changes W_r only, not the forces or the local fields)
/// Elements enter relaxed (delta = 0) and at rest relative to the wheel (u = 0) unless
/// BrushOptions::enter_at_road_velocity; they leave with their residual deflection.
///
/// Numerics (model spec, "Numerics"): variable-step BDF2 in time along the element path on an x grid
/// graded towards both edges (towards the leading edge more strongly where the transit 2a/V_r is as
/// short as the element's natural period, GridSpec::entry_transit_periods), and lateral strips
/// clustered towards the shoulders (sine-mapped midpoints, Gauss-Legendre nodes, or Gauss-Legendre
/// panels with two of three in the shoulder band of the Eq 8 pressure; more of them on that short-transit
/// grid, GridSpec::entry_strips, for the capture front in the shoulder band). Each implicit step treats
/// Coulomb friction as a set-valued law
/// at v_s = 0 (return mapping): stick if the trial stress is inside the static disc, else one monotone
/// scalar equation for |v_s| is solved by safeguarded Newton iteration in ln|v_s| (bounded iteration
/// count). The turn-slip coupling Omega delta in v_r is resolved by fixed-point iteration.
/// Optional local refinement (RefinementOptions): a step of one strip that ends sliding on the
/// velocity-weakening branch of Eq 10 with less than critical effective damping is redone in 2^L
/// substeps, within a fixed node budget per evaluation. Eq 20 is integrated by the trapezoid rule in x,
/// except that the sliding wear next to x = +-a, where p vanishes linearly and w_r ~ p^w1, gets the
/// exact weight h/(1 + w1) of that endpoint singularity.
///
/// Real-time layout (docs/performance.md): everything that depends only on the grid (node positions,
/// trapezoid weights, BDF2 coefficients, pressure shapes and their sat(p) factors, since
/// (p/p_ref)^-q separates into an x and a y factor) is precomputed at construction; per evaluation
/// the marcher sweeps x once with all strips side by side, so per-step quantities are computed once.
/// Each x step runs the strips in SIMD packs (src/model/brush_march.h: four strips per AVX2 register
/// where the CPU has AVX2 and FMA, else two per SSE2 register on x86-64, else one strip at a time):
/// the per-strip state is kept in structure-of-arrays form, every phase (history terms, trial stress
/// and stick test, slide root, update, wear law) runs on all lanes with masks instead of branches, the
/// slide roots of a pack iterate until all its lanes are done, and exp/log are glibc libmvec's vector
/// versions. 1.7x faster on the rig grid than the strips side by side in scalar code; the results agree
/// with one strip at a time to ~1e-14 relative (test SimdPacksAgreeWithOneStripAtATime).
/// The slide root starts from the previous node's root (warm start along the element path) or from the
/// closed-form creep root mu(|v_s|) p = |trial stress|; the wear law (Eq 19) reuses ln|v_s| and
/// |tau| = mu p (exact at the root), so it costs one exp and one log. Without turn slip and with
/// y_e = 0 the problem is mirror-symmetric in y and only half the strips are marched.
/// Memory: the per-strip state lives on the stack (sized for GridSpec::kMaxStrips strips: about 140 KB of
/// stack per call); evaluate()
/// allocates nothing, is const and thread-safe; its work is bounded by (n_x_steps * max(n_strips, entry_strips) +
/// refinement.node_budget) * turn_slip_iterations * (BrushOptions::max_root_iterations + 1) friction
/// evaluations (a step redone in substeps keeps its first, coarse, solve in the first term).
///
/// Outputs: Fx, Fy, Mz; W_r [kg/m] and wear per time [kg/s]; area fractions of stick by the paper's
/// Section 4 definition (v_s <= v_m) and of exact stick (v_s = 0); optionally the local fields.
/// Limits: steady state (no transient of the patch), rigid carcass, flat rectangular footprint,
/// no camber; the speed must be > 0 (standstill is the caller's convention, see WearModel).

#include <string>
#include <vector>

#include "tread_wear/model/adhesion_wear.h"
#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"
#include "tread_wear/model/operating_point.h"
#include "tread_wear/model/tire_params.h"

namespace tread_wear {

namespace march {  // the marcher's x step (src/model/brush_march.h)
struct StepArgs;
struct PathState;
struct NodeLanes;
struct RootCounts;
}  // namespace march

/// Lateral quadrature rule across the width y/b in [-1, 1].
enum class LateralRule {
  kSineMidpoint,        ///< midpoints of n equal cells in t, mapped y/b = sin(pi t/2) (clusters at the shoulders)
  kGaussLegendre,       ///< Gauss-Legendre nodes and weights (also clustered at the shoulders)
  kGaussShoulderPanels  ///< Gauss-Legendre on three panels per half, two of them in the pressure's shoulder band
};

/// Discretisation of the contact patch.
struct GridSpec {
  static constexpr int kMaxStrips = 256;  ///< bound of n_strips (the per-strip state lives on the stack)

  int n_x_steps = 200;        ///< element time steps across the contact length [-], >= 4
  int n_strips = 16;          ///< lateral strips [-], 1..kMaxStrips
  double edge_grading = 0.8;  ///< beta in x = a((1-beta) s + beta sin(pi s/2)): 0 uniform, -> 1 fine edges
  LateralRule lateral_rule = LateralRule::kSineMidpoint;
  /// Entry-transient grid (0: off). When an element crosses the patch within this many of its natural
  /// periods 2 pi sqrt(m/k_x) (2a/V_r short against the element dynamics: high speed), the patch
  /// response is mostly the element's transient from its entry state at x = +a; the leading half of the
  /// grid (x > 0) then uses entry_grading instead of edge_grading. Same node count, so same cost.
  double entry_transit_periods = 0.0;  ///< [-], >= 0
  double entry_grading = 0.0;          ///< beta of the leading half on the entry-transient grid [-], in [0, 1)
  /// Lateral strips on the entry-transient grid (0: n_strips) [-], same lateral rule. There the elements
  /// slide from the leading edge until the road captures them; where the pressure falls in the shoulder
  /// band the capture point runs to the trailing edge within a few hundredths of b, a steep front in the
  /// strip force across y that turn slip shifts differently on the two sides, and Mz follows that front.
  int entry_strips = 0;

  bool validate(std::string* error) const;
};

/// Local step refinement along the element path (per strip and x step). Sliding on the
/// velocity-weakening branch of the Savkoor law (|v_s| > v_m) with an effective damping
/// c + d(mu p)/d|v_s| along the slip below damping_ratio times the critical 2 sqrt(m k) makes the
/// element oscillate or run away (stick-slip bursts) on its own time scale 1/rate with
/// rate = max(sqrt(k/m), -c_eff/m); such a step is redone in 2^L equal substeps so that
/// rate h / 2^L <= resolution. The outputs of the strip are integrated over the substeps; local
/// fields stay on the coarse grid. Off with max_level = 0 (a fixed grid).
struct RefinementOptions {
  static constexpr int kMaxLevel = 8;  ///< bound of max_level
  int max_level = 0;                   ///< at most 2^max_level substeps per x step [-], 0..kMaxLevel; the model
                                       ///< keeps 2 (2^max_level - 1) doubles per x step for the substep nodes
  int node_budget = 0;                 ///< substep nodes allowed per evaluation, bounds the extra work [-]
  double resolution = 0.5;             ///< target rate * substep duration [-]
  double damping_ratio = 0.0;          ///< refine below this ratio of effective to critical damping [-]
                                       ///< (0: only unstable sliding, c + d(mu p)/d|v_s| < 0)

  bool validate(std::string* error) const;
};

struct BrushOptions {
  GridSpec grid;
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  bool enter_at_road_velocity = false;  ///< leading-edge alternative of the model spec (u = v_r)
  int turn_slip_iterations = 3;         ///< fixed-point passes for the Omega delta coupling, >= 1
  double creep_floor_mps = 1e-14;       ///< |v_s| below this counts as v_s -> 0+ (creep at the static limit)
  int max_root_iterations = 40;         ///< bound on Newton/bisection steps per slide root, >= 1
  double root_tolerance = 1e-7;         ///< stop when the Newton step in ln|v_s| is below this [-], (0, 0.1];
                                        ///< the last step is applied, so the error is O(tolerance^2)
  bool use_symmetry = true;             ///< march half the strips when straight (Omega = 0) and y_e = 0
  RefinementOptions refinement{};       ///< local substeps for stick-slip bursts (off by default)
  int max_simd_lanes = 4;               ///< widest pack of strips in SIMD lanes: 4 (AVX2 where the CPU has it,
                                        ///< else 2), 2 (SSE2), 1 (one strip at a time). Same model; results
                                        ///< differ by rounding and by where the root tolerance stops an iteration

  bool validate(std::string* error) const;
};

/// Global outputs of one evaluation. All SI.
struct WearResult {
  double fx_n = 0.0;                  ///< longitudinal force Fx [N]
  double fy_n = 0.0;                  ///< lateral (side) force Fy [N]
  double mz_nm = 0.0;                 ///< aligning moment Mz about the contact centre [N m]
  double wear_rate_kg_per_m = 0.0;    ///< global wear rate W_r per distance travelled [kg/m] (Eq 20)
  double wear_rate_kg_per_s = 0.0;    ///< global wear rate per time [kg/s] = W_r V
  double stick_fraction = 1.0;        ///< area fraction with |v_s| <= v_m (paper Section 4) [-]
  double slide_fraction = 0.0;        ///< 1 - stick_fraction [-]
  double exact_stick_fraction = 1.0;  ///< area fraction with v_s = 0 [-]
  double half_length_m = 0.0;         ///< contact half length a [m]
  double half_width_m = 0.0;          ///< contact half width b [m]
  int max_root_iterations = 0;        ///< worst scalar-solver iteration count in this evaluation [-]
  long root_iterations = 0;           ///< total scalar-solver iterations in this evaluation [-]
  int refined_substeps = 0;           ///< substep nodes of the local step refinement in this evaluation [-]
};

/// Local fields on the grid (node-major: index = i * n_strips + j, i along x from the leading edge).
struct PatchFields {
  int n_x_nodes = 0;
  int n_strips = 0;                 ///< strips of the last evaluation's grid (at most the y_m.size() that resize() set)
  std::vector<double> x_m;          ///< node x [m], size n_x_nodes
  std::vector<double> y_m;          ///< strip centre y [m], size n_strips
  std::vector<double> pressure_pa;  ///< p [Pa]
  std::vector<double> tau_x_pa, tau_y_pa;    ///< shear stress [Pa]
  std::vector<double> v_sx_mps, v_sy_mps;    ///< sliding velocity [m/s]
  std::vector<double> delta_x_m, delta_y_m;  ///< tip deflection [m]
  std::vector<double> wear_kg_per_m3;        ///< local wear rate w_r per area and distance [kg/(m m^2)]
  std::vector<unsigned char> state;          ///< 0 exact stick, 1 creep (0 < |v_s| <= v_m), 2 slide (|v_s| > v_m)

  void resize(int nx, int ny);
  int index(int i, int j) const { return i * n_strips + j; }
};

/// The paper's model, solved by marching BDF2 with return mapping. Construct once, evaluate often.
class BrushWearModel {
 public:
  /// @throw std::invalid_argument naming the field when params or options are invalid.
  BrushWearModel(const TireParams& params, const BrushOptions& options);

  /// Evaluates one steady operating point. The point must satisfy OperatingPoint::validate() and
  /// have speed_mps > 0 (then V_r > 0 too). Writes into caller-owned storage; allocates nothing.
  /// The paper's steps: footprint and pressure (ContactPatch, Eqs 6-9); the element march from the leading
  /// to the trailing edge (Eqs 12-18, brush_march.h), adding up forces, moment and wear (Eqs 19-20, 25).
  /// @param[in] op operating point
  /// @param[out] result global outputs
  /// @param[out] fields optional local fields, pre-sized with fields->resize(nodesX(), strips())
  void evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields = nullptr) const;

  int nodesX() const { return static_cast<int>(x_grid_.s.size()); }
  /// Strips of the widest lateral grid: size PatchFields with it. evaluate() sets fields->n_strips to
  /// the strips of the grid it used (the entry-transient grid may have more).
  int strips() const;
  const TireParams& params() const { return params_; }
  const BrushOptions& options() const { return options_; }

 private:
  /// Per x step (from node i to node i+1), grid-only quantities.
  struct Step {
    double ds;    ///< s_i - s_{i+1} [-]
    double a1;    ///< BDF2 coefficient on the state at node i [-]
    double a2;    ///< BDF2 coefficient on the state at node i-1 [-]
    double beta;  ///< BDF2 coefficient on the step (g = beta h) [-]
    double w;     ///< step ratio h_i / h_{i-1} [-] (1 on the first step)
  };
  /// Grid-only quantities along x.
  struct XGrid {
    std::vector<double> s;        ///< mapped node coordinate x/a, from +1 to -1
    std::vector<double> wx;       ///< trapezoid weight in x/a
    std::vector<double> gx_even;  ///< even part of g_x at the nodes
    std::vector<double> sat_gx;   ///< gx_even^-q at the nodes, 0 where gx_even = 0 (x factor of sat(p), Eq 11)
    /// gx_even and gx_even^-q at the interior substep nodes of the finest refinement level, 2^max_level - 1
    /// per step (index step * (2^max_level - 1) + m - 1 for the m-th); coarser levels use every 2^k-th.
    std::vector<double> sub_gx_even, sub_sat_gx;
    std::vector<Step> steps;  ///< per-step BDF2 coefficients
  };
  XGrid makeXGrid(double leading_grading) const;
  /// Grid-only quantities across y (the strips).
  struct YGrid {
    std::vector<double> eta;    ///< strip centre y/b
    std::vector<double> wy;     ///< strip weight in y/b (sums to 2)
    std::vector<double> gy;     ///< g_y at the strip centres
    std::vector<double> sat_y;  ///< g_y^-q at the strip centres (y factor of sat(p))
    bool symmetric = false;     ///< g_y even (y_e = 0) and the strip rule mirror-symmetric
  };
  YGrid makeYGrid(int n_strips) const;
  /// Whether an element crosses the patch of half length a within entry_transit_periods of its natural
  /// period 2 pi sqrt(m/k_x) (k_x from Eq 13) at this rolling speed: then the entry-transient grids apply.
  bool entryTransient(double half_length_m, double kx_pa_per_m, double rolling_speed_mps) const;
  /// One evaluation's march across the patch: its constants and its workspace on evaluate()'s stack.
  class Sweep;

  TireParams params_;
  BrushOptions options_;
  AdhesionWear adhesion_;  ///< the road extension's adhesion-zone term (off when its coefficient is 0)
  SavkoorFriction friction_;
  ShiftSaturation shift_saturation_;  ///< (1 - B x/a)^-q, the centre shift's factor of sat(p)
  PressureShape gx_;                  ///< g_x without the centre shift (its even part)
  XGrid x_grid_;                      ///< edge_grading at both edges
  XGrid entry_x_grid_;                ///< entry_grading at the leading edge (when the entry grid is on)
  YGrid y_grid_;                      ///< n_strips
  YGrid entry_y_grid_;                ///< entry_strips (empty when the entry grid keeps n_strips)
  /// The x step of the strips side by side: packs of strips in SIMD lanes where the CPU allows
  /// (chosen once, here), else one strip after the other.
  void (*advance_)(const march::StepArgs&, int first, int count, const march::PathState& from, march::PathState* to,
                   march::NodeLanes*, march::RootCounts*);
};

}  // namespace tread_wear
