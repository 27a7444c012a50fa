#pragma once
/// @file brush_march.h
/// Internal to BrushWearModel::evaluate (src/model/brush_wear_model.cpp): the per-strip work of one
/// implicit x step of the marcher (history terms, trial stress and stick test, slide root, update,
/// wear law Eq 19), written once for a lane type V: `double` (one strip) or a SIMD pack of
/// neighbouring strips (brush_march_avx2.cpp: 4 per AVX2 register, brush_march_sse2.cpp: 2 per SSE2
/// register). The physics is documented in brush_wear_model.h.
///
/// Why packs: per node the work is a short chain of exp, log and divisions per strip (the slide root
/// is a Newton iteration in ln|v_s|); the strips of one x step are independent, so W strips go through
/// every phase in the W lanes of a vector register, with libmvec's vector exp/log. To make that pay,
/// the per-strip state lives permanently in structure-of-arrays form (PathState, NodeLanes: no gather),
/// branches are masks and blends, and the slide roots of a pack iterate until all its lanes are done.
/// A branch whose work is rare (bisection, creep start, the wear law in deep creep) is still skipped
/// when no lane of the pack takes it (`any`), so the scalar instance does what the branchy code did.

#include <cmath>

#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {
namespace march {

constexpr int kMaxLanes = 8;                                   ///< widest pack
constexpr int kCapacity = GridSpec::kMaxStrips + kMaxLanes;    ///< a pack may run past the last strip

/// Coefficients of the variable-step BDF2 step y_{i+1} = a1 y_i + a2 y_{i-1} + beta h_i y'_{i+1}.
struct Bdf2 {
  double a1, a2, beta;
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

/// StepTerms per strip, for an x step in which some strips come back from substeps (other BDF2 ratio).
struct StepTermLanes {
  alignas(64) double g[kCapacity], m_over_g[kCapacity], dx[kCapacity], dy[kCapacity];
  alignas(64) double inv_dx[kCapacity], inv_dy[kCapacity], w[kCapacity], a1[kCapacity], a2[kCapacity];

  void set(int j, const StepTerms& t) {
    g[j] = t.g, m_over_g[j] = t.m_over_g, dx[j] = t.dx, dy[j] = t.dy, inv_dx[j] = t.inv_dx, inv_dy[j] = t.inv_dy;
    w[j] = t.w, a1[j] = t.c.a1, a2[j] = t.c.a2;
  }
};

/// Scalars of one evaluation that the step needs (SI units, as in evaluate()).
struct Constants {
  double vrx0, vry0;          ///< rolling slip velocity without turn slip [m/s]
  double omega;               ///< yaw rate over the road [rad/s]
  double kx, ky;              ///< element stiffness [Pa/m]
  double p_0;                 ///< pressure below which sat(p) is held [Pa]
  double sat_floor;           ///< sat(p_0) [-]
  double mu_0, dmu, savkoor_c, ln_vm;  ///< Savkoor law in l = ln(|v_s|/v_m): mu_0 + dmu exp(-c l^2)
  double z_floor;             ///< ln of the creep floor speed
  double savkoor_floor;       ///< mu/sat(p) at the creep floor [-]
  double tol;                 ///< root tolerance in ln|v_s| [-]
  int max_iterations;         ///< bound on root iterations
  int passes;                 ///< turn-slip fixed-point passes
  double w1, w2, w4;          ///< wear law exponents and the constant term [kg/(s m^2)]
  double ln_w3_over_mpa_w1;   ///< ln(w3 / (1 MPa)^w1)
  double z_wear_cut;          ///< ln|v_s| below which the sliding wear term is skipped
  double v_m;                 ///< sliding speed of peak friction: the stick fraction counts |v_s| <= v_m [m/s]
  bool refine;                ///< compute NodeLanes::refine_rate (local refinement on)
  double m, cx, cy;           ///< element mass [kg/m^2] and damping [Pa s/m]
  double damping_ratio;       ///< refine below this ratio of effective to critical damping [-]
};

/// Strip constants of one evaluation.
struct StripConstants {
  alignas(64) double y[kCapacity];      ///< strip centre [m]
  alignas(64) double gy[kCapacity];     ///< g_y [-]
  alignas(64) double sat_y[kCapacity];  ///< g_y^-q (y factor of sat(p)) [-]
  alignas(64) double weight[kCapacity];  ///< area weight in y/b of the strip (x 2 for a mirrored pair; 0 past the last)
  alignas(64) double y_mz[kCapacity];   ///< lever arm of tau_x in Mz [m] (0 for mirrored pairs, whose terms cancel)
};

/// State of the element travelling along each strip (structure of arrays, index = strip).
struct PathState {
  alignas(64) double dlx[kCapacity], dly[kCapacity];      ///< deflection at the current node [m]
  alignas(64) double ux[kCapacity], uy[kCapacity];        ///< its rate [m/s]
  alignas(64) double dlx_p[kCapacity], dly_p[kCapacity];  ///< the same at the previous node (BDF2)
  alignas(64) double ux_p[kCapacity], uy_p[kCapacity];
  alignas(64) double z[kCapacity];          ///< ln|v_s| at the current node if it slid (warm start)
  alignas(64) double z_p[kCapacity];        ///< ln|v_s| at the previous node if it slid
  alignas(64) double sliding[kCapacity];    ///< 1 if the current node slid with |v_s| > 0, else 0
  alignas(64) double sliding_p[kCapacity];  ///< the same at the previous node
};

/// Node solutions of one x step (structure of arrays, index = strip).
struct NodeLanes {
  alignas(64) double p[kCapacity];               ///< pressure [Pa]
  alignas(64) double tx[kCapacity], ty[kCapacity];    ///< shear stress [Pa]
  alignas(64) double vsx[kCapacity], vsy[kCapacity];  ///< sliding velocity [m/s]
  alignas(64) double s[kCapacity], z[kCapacity];      ///< |v_s| [m/s] and ln|v_s| (0 when not sliding)
  alignas(64) double mup[kCapacity];             ///< mu p at the slide root [Pa]
  alignas(64) double s_dmup[kCapacity];          ///< |v_s| d(mu p)/d|v_s| at the slide root [Pa]
  alignas(64) double wt[kCapacity];              ///< wear per time and area, Eq 19 [kg/(s m^2)]
  alignas(64) double stuck[kCapacity];           ///< 1 for exact stick (v_s = 0), else 0
  /// Where the step ends sliding on the velocity-weakening branch with an effective damping c + d(mu p)/d|v_s|
  /// along the slip below damping_ratio x critical: the element's own rate max(sqrt(k/m), -c_eff/m) that
  /// substeps must resolve [1/s]; else 0.
  alignas(64) double refine_rate[kCapacity];
};

/// The path state and node solution of one strip, set aside while a range of strips before it is redone in
/// substeps: a pack that runs past the range's last strip writes the next strips' lanes too.
struct LaneCopy {
  double state[12];
  double node[12];
};

inline constexpr double (PathState::*kStateFields[12])[kCapacity] = {
    &PathState::dlx, &PathState::dly, &PathState::ux,    &PathState::uy, &PathState::dlx_p,   &PathState::dly_p,
    &PathState::ux_p, &PathState::uy_p, &PathState::z, &PathState::z_p, &PathState::sliding, &PathState::sliding_p};
inline constexpr double (NodeLanes::*kNodeFields[12])[kCapacity] = {
    &NodeLanes::p, &NodeLanes::tx,  &NodeLanes::ty,  &NodeLanes::vsx, &NodeLanes::vsy,   &NodeLanes::s,
    &NodeLanes::z, &NodeLanes::mup, &NodeLanes::s_dmup, &NodeLanes::wt, &NodeLanes::stuck, &NodeLanes::refine_rate};

inline void saveLane(const PathState& state, const NodeLanes& nodes, int j, LaneCopy* copy) {
  for (int f = 0; f < 12; ++f) copy->state[f] = (state.*kStateFields[f])[j];
  for (int f = 0; f < 12; ++f) copy->node[f] = (nodes.*kNodeFields[f])[j];
}

inline void restoreLane(const LaneCopy& copy, int j, PathState* state, NodeLanes* nodes) {
  for (int f = 0; f < 12; ++f) (state->*kStateFields[f])[j] = copy.state[f];
  for (int f = 0; f < 12; ++f) (nodes->*kNodeFields[f])[j] = copy.node[f];
}

/// Quadrature sums over the nodes of the evaluation (Eq 20), per lane (added up by the caller at the end).
struct PatchSums {
  double fx[kMaxLanes], fy[kMaxLanes];  ///< sum of dA tau [N]
  double mz[kMaxLanes];                 ///< sum of dA (x tau_y - y_mz tau_x) [N m]
  double wear[kMaxLanes];               ///< sum of dA wear per time and area [kg/s]
  double stick[kMaxLanes];              ///< sum of dA (|v_s| <= v_m) [m^2]
  double exact[kMaxLanes];              ///< sum of dA (v_s = 0) [m^2]
};

/// The node an x step goes to.
struct Node {
  double x;      ///< x [m]
  double px;     ///< pressure over g_y [Pa]
  double sat_x;  ///< x factor of sat(p) [-]
};

/// Root iteration counts of an evaluation (WearResult).
struct RootCounts {
  int max_iterations = 0;
  long total = 0;
};

/// Arguments of one x step of strips [first, first + count): per-step terms `uniform` for all of them,
/// unless `per_strip` is given.
struct StepArgs {
  const Constants* k;
  const StripConstants* strips;
  const StepTerms* uniform;
  const StepTermLanes* per_strip;
  Node node;
  double node_area;  ///< trapezoid weight of the node in x times a b [m^2] (dA = node_area x strip weight)
  PatchSums* sums;   ///< where to add the node solutions, or nullptr
};

/// Advances strips [first, first + count) by one x step from the path state `from` to `to` (may be the
/// same) and writes their node solutions to `out`.
using AdvanceFunction = void (*)(const StepArgs& args, int first, int count, const PathState& from, PathState* to,
                                 NodeLanes* out, RootCounts* counts);

/// One strip after the other (any machine).
void advanceScalar(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                   RootCounts* counts);

#ifdef TREAD_WEAR_SIMD_MARCHER
/// Two strips per SSE2 pack (the x86-64 baseline).
void advanceSse2(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                 RootCounts* counts);
/// Four strips per AVX2 pack; call only where the CPU has AVX2 and FMA.
void advanceAvx2(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                 RootCounts* counts);
#endif

/// The fastest advance this CPU and build run with at most `max_lanes` strips per pack (decided once).
AdvanceFunction fastestAdvance(int max_lanes);

namespace {

// Lane operations on double, for the one-strip instance. A pack type provides the same set.
inline bool any(bool m) { return m; }
inline double select(bool m, double a, double b) { return m ? a : b; }
inline double vexp(double v) { return std::exp(v); }
inline double vlog(double v) { return std::log(v); }
inline double vlog1p(double v) { return std::log1p(v); }
inline double vsqrt(double v) { return std::sqrt(v); }
inline double vabs(double v) { return std::fabs(v); }
inline double vmin(double a, double b) { return b < a ? b : a; }
inline double vmax(double a, double b) { return a < b ? b : a; }

template <class V>
struct LaneTraits;

template <>
struct LaneTraits<double> {
  using Mask = bool;
  static constexpr int kWidth = 1;
  static double load(const double* p) { return *p; }
  static void store(double* p, double v) { *p = v; }
  static bool firstLanes(int) { return true; }
  static bool none() { return false; }
  static int maxLane(double v) { return static_cast<int>(v); }
  static long sumLanes(double v) { return static_cast<long>(v); }
};

// The phases of one implicit x step of a pack of strips, in the order advancePack runs them. Each is a small
// inline template: advancePack must stay one function after inlining (the hot loop keeps its values in
// registers, and FMA contraction in the AVX2 build sees the same expressions).

/// Per-step terms of a pack (StepTerms in lanes): the same for all its strips unless some come back from
/// substeps.
template <class V>
struct PackStep {
  V g;               ///< beta h [s]
  V m_over_g;        ///< m / g [Pa s/m]
  V dx, dy;          ///< D = m/g + c + k g [Pa s/m]
  V inv_dx, inv_dy;  ///< 1/D [m/(Pa s)]
  V w;               ///< step ratio h_i / h_{i-1} [-]
  V a1, a2;          ///< BDF2 coefficients on the states at nodes i and i - 1 [-]
};

template <class V>
inline PackStep<V> packStep(const StepArgs& args, int j) {
  using T = LaneTraits<V>;
  const StepTermLanes* ps = args.per_strip;
  const StepTerms& u = *args.uniform;
  if (!ps) return {V(u.g), V(u.m_over_g), V(u.dx), V(u.dy), V(u.inv_dx), V(u.inv_dy), V(u.w), V(u.c.a1), V(u.c.a2)};
  return {T::load(ps->g + j),  T::load(ps->m_over_g + j), T::load(ps->dx + j),
          T::load(ps->dy + j), T::load(ps->inv_dx + j),   T::load(ps->inv_dy + j),
          T::load(ps->w + j),  T::load(ps->a1 + j),       T::load(ps->a2 + j)};
}

/// What the implicit step of a pack to node i + 1 needs: the pressure and static limit there (Eqs 8, 10-11) and the
/// element's past (the BDF2 history of m u' = tau - k o delta - c o u, Eqs 12 and 17).
template <class V>
struct PackHistory {
  using M = typename LaneTraits<V>::Mask;
  V p;                   ///< pressure [Pa]
  V sat_p;               ///< sat(p) p [Pa]
  V tau_static;          ///< static limit mu_0 sat(p) p [Pa]
  V dhx, dhy;            ///< BDF2 history of delta [m]
  V bx, by;              ///< history terms of the implicit update [Pa]
  V ux, uy;              ///< u at node i [m/s]
  V z, z_p;              ///< ln|v_s| at nodes i and i - 1 where the element slid there
  M sliding, sliding_p;  ///< slid with |v_s| > 0 at node i, at node i - 1
};

/// Loads node i's state of the pack from `from` and moves it to the previous-node slots of `to` (which may be
/// `from`: every load comes first). Stored here, before the root iteration, so that these values need not be
/// kept across its calls, which clobber every vector register.
template <class V>
inline PackHistory<V> packHistory(const StepArgs& args, int j, const PackStep<V>& st, const PathState& from,
                                  PathState* to) {
  using T = LaneTraits<V>;
  const Constants& k = *args.k;
  const StripConstants& sc = *args.strips;
  PackHistory<V> h;
  h.p = V(args.node.px) * T::load(sc.gy + j);
  const V sat = select(h.p > V(k.p_0), V(args.node.sat_x) * T::load(sc.sat_y + j), V(k.sat_floor));
  h.sat_p = sat * h.p;
  h.tau_static = V(k.mu_0) * h.sat_p;
  const V dlx = T::load(from.dlx + j), dly = T::load(from.dly + j);
  h.ux = T::load(from.ux + j);
  h.uy = T::load(from.uy + j);
  h.z = T::load(from.z + j);
  h.z_p = T::load(from.z_p + j);
  h.sliding = T::load(from.sliding + j) != V(0.0);
  h.sliding_p = T::load(from.sliding_p + j) != V(0.0);
  h.dhx = st.a1 * dlx + st.a2 * T::load(from.dlx_p + j);
  h.dhy = st.a1 * dly + st.a2 * T::load(from.dly_p + j);
  const V uhx = st.a1 * h.ux + st.a2 * T::load(from.ux_p + j), uhy = st.a1 * h.uy + st.a2 * T::load(from.uy_p + j);
  h.bx = st.m_over_g * uhx - V(k.kx) * h.dhx;
  h.by = st.m_over_g * uhy - V(k.ky) * h.dhy;
  T::store(to->dlx_p + j, dlx);
  T::store(to->dly_p + j, dly);
  T::store(to->ux_p + j, h.ux);
  T::store(to->uy_p + j, h.uy);
  T::store(to->sliding_p + j, select(h.sliding, V(1.0), V(0.0)));
  T::store(to->z_p + j, h.z);
  return h;
}

/// The pack's solution at node i + 1 (updated by each turn-slip pass).
template <class V>
struct PackNode {
  using M = typename LaneTraits<V>::Mask;
  V tx, ty;       ///< shear stress tau [Pa]
  V vsx, vsy;     ///< sliding velocity v_s [m/s]
  V s, z;         ///< |v_s| [m/s] and ln|v_s| (0 when not sliding)
  V mup, s_dmup;  ///< mu p and |v_s| d(mu p)/d|v_s| at the last slide root [Pa]
  V ux, uy;       ///< u [m/s]
  V dlx, dly;     ///< delta [m]; before the first pass the predictor for the Omega delta coupling
  M stuck;        ///< exact stick
};

/// The stress needed to stick at node i + 1 (trial stress of the return mapping) and its squares [Pa, Pa^2].
template <class V>
struct TrialStress {
  V tx, ty;
  V t2x, t2y, t2;
};

/// Trial stress D o v_r - b with v_r at the tip's position from the deflection n.dlx, n.dly (Eq 14 generalised:
/// TipKinematics::vrx and vry in lanes).
template <class V>
inline TrialStress<V> trialStress(const Constants& k, const Node& node, const PackStep<V>& st, const PackHistory<V>& h,
                                  const V& y, const PackNode<V>& n) {
  const V rx = V(k.vrx0) + V(k.omega) * (y + n.dly), ry = V(k.vry0) - V(k.omega) * (V(node.x) + n.dlx);
  TrialStress<V> t;
  t.tx = st.dx * rx - h.bx;
  t.ty = st.dy * ry - h.by;
  t.t2x = t.tx * t.tx;
  t.t2y = t.ty * t.ty;
  t.t2 = t.t2x + t.t2y;
  return t;
}

/// mu p and |v_s| d(mu p)/d|v_s| [Pa] at z = ln|v_s| (Eq 10 times sat(p) p, sat_p = sat(p) p).
template <class V>
inline void frictionStress(const Constants& k, const V& sat_p, const V& z, V* mup, V* s_dmup) {
  const V l = z - V(k.ln_vm);
  const V e = V(k.dmu) * vexp(V(-k.savkoor_c) * l * l);
  *mup = sat_p * (V(k.mu_0) + e);
  *s_dmup = sat_p * e * (V(-2.0 * k.savkoor_c) * l);
}

/// Bracket [lo, hi] of the slide root in z = ln|v_s|: lo = ln of the creep floor; the upper end ln(|t| / min D)
/// is computed only where bisection needs it (infinite until then).
template <class V>
struct RootBracket {
  using M = typename LaneTraits<V>::Mask;
  V lo, hi;

  void needUpper(const M& lanes, const TrialStress<V>& t, const PackStep<V>& st) {
    const M need = lanes & (hi == V(__builtin_inf()));
    if (any(need)) hi = select(need, vlog(select(need, vsqrt(t.t2) / vmin(st.dx, st.dy), V(1.0))), hi);
  }
};

/// Slide root of a pack: |v_s|, ln|v_s|, mu p and |v_s| d(mu p)/d|v_s| there, iterations spent.
template <class V>
struct SlideRoot {
  V s, z, mup, s_dmup;
  V iterations;
};

/// Start of the root iteration in the lanes `solving`: the previous pass at this node (n), else ln|v_s|
/// extrapolated along the element path; on the rising branch of mu the closed-form creep root; inside the bracket.
template <class V>
inline V rootStart(const Constants& k, const PackStep<V>& st, const PackHistory<V>& h, const TrialStress<V>& t,
                   const PackNode<V>& n, const typename LaneTraits<V>::Mask& solving, RootBracket<V>* bracket) {
  using M = typename LaneTraits<V>::Mask;
  const M have_guess = (n.s > V(0.0)) | h.sliding;
  V zi = select(n.s > V(0.0), n.z, select(h.sliding_p, h.z + st.w * (h.z - h.z_p), h.z));
  const M rising_start = solving & ((!have_guess) | (zi < V(k.ln_vm)));
  if (any(rising_start)) {
    // Closed-form creep root mu(s) p = |t| with D s neglected, on the rising branch (s < v_m): there it
    // is a better start than the warm start; beyond the peak of mu the warm start is.
    const V r = vsqrt(t.t2);
    const V e = (r / h.sat_p - V(k.mu_0)) / V(k.dmu);
    const M closed = rising_start & (e > V(0.0)) & (e < V(1.0));
    if (any(closed)) zi = select(closed, V(k.ln_vm) - vsqrt(-vlog(select(closed, e, V(1.0))) / V(k.savkoor_c)), zi);
    // Viscous estimate: D s carries what friction at its floor mu_0 p does not.
    const M viscous = rising_start & !closed & !have_guess;
    if (any(viscous)) {
      const V s_visc = vsqrt(t.t2x / (st.dx * st.dx) + t.t2y / (st.dy * st.dy));
      const V estimate = vmax(s_visc * (V(1.0) - h.sat_p * V(k.mu_0) / r), V(1e-300));
      zi = select(viscous, vlog(select(viscous, estimate, V(1.0))), zi);
    }
  }
  const M outside = solving & !((zi > bracket->lo) & (zi < bracket->hi));
  if (any(outside)) {
    bracket->needUpper(outside, t, st);
    zi = select(outside, V(0.5) * (bracket->lo + bracket->hi), zi);
  }
  return select(solving, zi, V(0.0));  // lanes not solving evaluate a harmless residual
}

/// Slide root in the lanes `solving` (the return mapping's slide branch, Eqs 10, 16-18): F(z) = sum_i t_i^2 /
/// (D_i s + mu(s) p)^2 - 1 = 0 in z = ln s, s = |v_s|, monotone decreasing while D_i + p dmu/ds > 0. Newton in z
/// on ln(F + 1), safeguarded by bisection on the bracket, at most max_iterations per lane; the slide roots of a
/// pack iterate until all its lanes are done.
template <class V>
inline SlideRoot<V> slideRoot(const Constants& k, const PackStep<V>& st, const PackHistory<V>& h,
                              const TrialStress<V>& t, typename LaneTraits<V>::Mask solving, V zi,
                              RootBracket<V> bracket) {
  using M = typename LaneTraits<V>::Mask;
  SlideRoot<V> root{V(0.0), V(0.0), V(0.0), V(0.0), V(0.0)};
  while (any(solving)) {
    // Residual F and dF/dz at zi.
    const V rs = vexp(zi);
    V rmup, rs_dmup;
    frictionStress(k, h.sat_p, zi, &rmup, &rs_dmup);
    const V gx = st.dx * rs + rmup, gy = st.dy * rs + rmup;
    const V inv = V(1.0) / (gx * gy);  // one division for both reciprocals
    const V igx = gy * inv, igy = gx * inv;
    const V fx = t.t2x * igx * igx, fy = t.t2y * igy * igy;
    const V dfdz = V(-2.0) * (fx * (st.dx * rs + rs_dmup) * igx + fy * (st.dy * rs + rs_dmup) * igy);
    const V f = fx + fy - V(1.0);

    // Safeguarded Newton step.
    root.iterations = select(solving, root.iterations + V(1.0), root.iterations);
    const M above = f > V(0.0);
    bracket.lo = select(solving & above, zi, bracket.lo);
    bracket.hi = select(solving & !above, zi, bracket.hi);
    // Far from the root F + 1 behaves like a power of s (like s^-2 where D s dominates), so Newton
    // on ln(F + 1) is nearly linear in z there; near the root both forms agree to O(F^2).
    const M descending = dfdz < V(0.0);
    const M far = solving & descending & !(vabs(f) < V(0.25));
    V numerator = -f;
    if (any(far)) numerator = select(far, -(V(1.0) + f) * vlog1p(select(far, f, V(0.0))), numerator);
    const V step = select(descending, numerator / dfdz, V(0.0));
    // Quadratic convergence: the remaining error is O(step^2); correct s and mu p to first order.
    const M converged = solving & descending & (vabs(step) < V(k.tol));
    root.z = select(converged, zi + step, root.z);
    root.s = select(converged, rs * (V(1.0) + step), root.s);
    root.mup = select(converged, rmup + rs_dmup * step, root.mup);
    root.s_dmup = select(converged, rs_dmup, root.s_dmup);
    solving = solving & !converged;
    V z_new = zi + step;
    const M bisect = solving & ((!descending) | (!((z_new > bracket.lo) & (z_new < bracket.hi))));
    if (any(bisect)) {
      bracket.needUpper(bisect, t, st);
      z_new = select(bisect, V(0.5) * (bracket.lo + bracket.hi), z_new);
    }
    const M exhausted = solving & ((bracket.hi - bracket.lo < V(k.tol)) | (root.iterations == V(k.max_iterations)));
    if (any(exhausted)) {
      const V ze = select(exhausted, z_new, V(0.0));
      V mup_e, s_dmup_e;
      frictionStress(k, h.sat_p, ze, &mup_e, &s_dmup_e);
      root.z = select(exhausted, ze, root.z);
      root.s = select(exhausted, vexp(ze), root.s);
      root.mup = select(exhausted, mup_e, root.mup);
      root.s_dmup = select(exhausted, s_dmup_e, root.s_dmup);
      solving = solving & !exhausted;
    }
    zi = select(solving, z_new, zi);
  }
  return root;
}

/// Node solution of the lanes `slid` (not stuck): slide at the root, or, where even the floor speed's friction
/// holds the trial stress (root.s = 0), creep at the static limit along the trial direction. Stuck lanes take the
/// trial stress. Then u and delta at the node from the implicit update.
template <class V>
inline void nodeSolution(const PackStep<V>& st, const PackHistory<V>& h, const TrialStress<V>& t,
                         const SlideRoot<V>& root, const typename LaneTraits<V>::Mask& slid, PackNode<V>* n) {
  using M = typename LaneTraits<V>::Mask;
  const M sliding = slid & (root.s > V(0.0));
  const M creeping = slid & !(root.s > V(0.0));
  const V gx = st.dx * root.s + root.mup, gy = st.dy * root.s + root.mup;
  const V inv = V(1.0) / select(sliding, gx * gy, V(1.0));
  const V igx = gy * inv, igy = gx * inv;
  n->tx = select(n->stuck, t.tx, root.mup * t.tx * igx);
  n->ty = select(n->stuck, t.ty, root.mup * t.ty * igy);
  if (any(creeping)) {
    const V static_over_tt = h.tau_static / select(creeping, vsqrt(t.t2), V(1.0));
    n->tx = select(creeping, static_over_tt * t.tx, n->tx);
    n->ty = select(creeping, static_over_tt * t.ty, n->ty);
  }
  n->vsx = select(sliding, -t.tx * root.s * igx, V(0.0));
  n->vsy = select(sliding, -t.ty * root.s * igy, V(0.0));
  n->s = select(n->stuck, V(0.0), root.s);
  n->z = select(sliding, root.z, V(0.0));
  n->mup = select(sliding, root.mup, n->mup);
  n->s_dmup = select(sliding, root.s_dmup, n->s_dmup);
  n->ux = (n->tx + h.bx) * st.inv_dx;
  n->uy = (n->ty + h.by) * st.inv_dy;
  n->dlx = h.dhx + st.g * n->ux;
  n->dly = h.dhy + st.g * n->uy;
}

/// Eq 19 per time and area [kg/(s m^2)]; at the slide root |tau| = mu p exactly, and ln|v_s| = z is known. Below
/// z_wear_cut the sliding term is under 1e-9 w4 (deep creep) and is skipped.
template <class V>
inline V wearPerTime(const Constants& k, const PackNode<V>& n) {
  using M = typename LaneTraits<V>::Mask;
  V wt(k.w4);
  const M wearing = (n.s > V(0.0)) & (n.z > V(k.z_wear_cut));
  if (any(wearing)) {
    const V ln_mup = vlog(select(wearing, n.mup, V(1.0)));
    const V sliding_wear = vexp(V(k.ln_w3_over_mpa_w1) + V(k.w1) * ln_mup + V(k.w2) * n.z);
    wt = select(wearing, V(k.w4) + sliding_wear, wt);
  }
  return wt;
}

/// NodeLanes::refine_rate [1/s] of the real lanes: the element's own rate max(sqrt(k/m), -c_eff/m) where it slides
/// faster than v_m with an effective damping c_eff = c + d(mu p)/d|v_s| along the slip below damping_ratio times
/// the critical 2 sqrt(m k); else 0.
template <class V>
inline V refineRate(const Constants& k, const typename LaneTraits<V>::Mask& real, const PackNode<V>& n) {
  using M = typename LaneTraits<V>::Mask;
  V refine_rate(0.0);
  const M fast = real & (n.s > V(k.v_m));
  if (any(fast)) {
    const V s_fast = select(fast, n.s, V(1.0));
    const V inv_s2 = V(1.0) / (s_fast * s_fast);
    const V nx2 = n.vsx * n.vsx * inv_s2, ny2 = V(1.0) - nx2;  // squared slip direction
    const V k_dir = V(k.kx) * nx2 + V(k.ky) * ny2;
    const V c_eff = V(k.cx) * nx2 + V(k.cy) * ny2 + n.s_dmup * s_fast * inv_s2;
    const V c_crit = V(2.0) * vsqrt(V(k.m) * k_dir);
    const M weakly_damped = fast & !(c_eff >= V(k.damping_ratio) * c_crit);
    if (any(weakly_damped)) {
      const V inv_m(1.0 / k.m);
      refine_rate = select(weakly_damped, vmax(vsqrt(k_dir * inv_m), -c_eff * inv_m), refine_rate);
    }
  }
  return refine_rate;
}

/// Adds the real lanes' node solution times dA to the sums of Eq 20 (lanes past the last strip add nothing).
template <class V>
inline void addToSums(const StepArgs& args, int j, const typename LaneTraits<V>::Mask& real, const PackNode<V>& n,
                      const V& wt) {
  using T = LaneTraits<V>;
  const Constants& k = *args.k;
  PatchSums& sum = *args.sums;
  const V area = V(args.node_area) * T::load(args.strips->weight + j);  // dA [m^2]
  const V zero(0.0);
  const V force_x = select(real, area * n.tx, zero), force_y = select(real, area * n.ty, zero);
  T::store(sum.fx, T::load(sum.fx) + force_x);
  T::store(sum.fy, T::load(sum.fy) + force_y);
  T::store(sum.mz, T::load(sum.mz) + (V(args.node.x) * force_y - T::load(args.strips->y_mz + j) * force_x));
  T::store(sum.wear, T::load(sum.wear) + select(real, area * wt, zero));
  T::store(sum.stick, T::load(sum.stick) + select(real & (n.s <= V(k.v_m)), area, zero));
  T::store(sum.exact, T::load(sum.exact) + select(real & n.stuck, area, zero));
}

/// One x step of the W strips [j, j + W) of which the first `valid` are real (the pack of a lane type V),
/// from the path state `from` to `to` (may be `from`): the implicit BDF2 step of Eqs 12 and 17 with the return
/// mapping of Eqs 10, 16-18 (stick if the trial stress is inside the static disc, else slide at the root), repeated
/// for the Omega delta coupling of v_r; then the wear law (Eq 19) and the node's terms of Eq 20.
template <class V>
inline void advancePack(const StepArgs& args, int j, int valid, const PathState& from, PathState* to, NodeLanes* out,
                        RootCounts* counts) {
  using T = LaneTraits<V>;
  using M = typename T::Mask;
  const Constants& k = *args.k;
  const PackStep<V> st = packStep<V>(args, j);
  const M real = T::firstLanes(valid);
  const V y = T::load(args.strips->y + j);
  const PackHistory<V> h = packHistory(args, j, st, from, to);
  PackNode<V> n{V(0.0), V(0.0), V(0.0), V(0.0), V(0.0), V(0.0), V(0.0), V(0.0), V(0.0), V(0.0),
                h.dhx + st.g * h.ux, h.dhy + st.g * h.uy, T::none()};

  for (int pass = 0; pass < k.passes; ++pass) {
    const TrialStress<V> t = trialStress(k, args.node, st, h, y, n);
    n.stuck = t.t2 <= h.tau_static * h.tau_static;
    // Creep test at the floor speed: there D s is negligible against mu p and mu = mu(floor).
    const V mup_floor = h.sat_p * V(k.savkoor_floor);
    const M creep = t.t2 <= mup_floor * mup_floor;
    const M solving = real & !n.stuck & !creep;
    RootBracket<V> bracket{V(k.z_floor), V(__builtin_inf())};
    const V z_start = rootStart(k, st, h, t, n, solving, &bracket);
    const SlideRoot<V> root = slideRoot(k, st, h, t, solving, z_start, bracket);
    const M slid = real & !n.stuck;
    const int pack_max_iterations = T::maxLane(select(slid, root.iterations, V(0.0)));
    if (pack_max_iterations > counts->max_iterations) counts->max_iterations = pack_max_iterations;
    counts->total += T::sumLanes(select(slid, root.iterations, V(0.0)));
    nodeSolution(st, h, t, root, slid, &n);
  }

  T::store(to->dlx + j, n.dlx);
  T::store(to->dly + j, n.dly);
  T::store(to->ux + j, n.ux);
  T::store(to->uy + j, n.uy);
  T::store(to->sliding + j, select(n.s > V(0.0), V(1.0), V(0.0)));
  T::store(to->z + j, n.z);
  const V wt = wearPerTime(k, n);
  const V refine_rate = k.refine ? refineRate(k, real, n) : V(0.0);
  if (args.sums) addToSums(args, j, real, n, wt);
  T::store(out->refine_rate + j, refine_rate);
  T::store(out->p + j, h.p);
  T::store(out->tx + j, n.tx);
  T::store(out->ty + j, n.ty);
  T::store(out->vsx + j, n.vsx);
  T::store(out->vsy + j, n.vsy);
  T::store(out->s + j, n.s);
  T::store(out->z + j, n.z);
  T::store(out->mup + j, n.mup);
  T::store(out->s_dmup + j, n.s_dmup);
  T::store(out->wt + j, wt);
  T::store(out->stuck + j, select(n.stuck, V(1.0), V(0.0)));
}

/// One x step of strips [first, first + count) in packs of the lane type V (an AdvanceFunction's body).
template <class V>
inline void advanceInPacks(const StepArgs& args, int first, int count, const PathState& from, PathState* to,
                           NodeLanes* out, RootCounts* counts) {
  for (int j = first; j < first + count; j += LaneTraits<V>::kWidth)
    advancePack<V>(args, j, first + count - j, from, to, out, counts);
}

}  // namespace
}  // namespace march
}  // namespace tread_wear
