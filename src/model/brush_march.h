#pragma once
/// @file brush_march.h
/// Internal to BrushWearModel::evaluate (src/core/brush_wear_model.cpp): the per-strip work of one
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

/// One x step of the W strips [j, j + W) of which the first `valid` are real (the pack of a lane type V),
/// from the path state `from` to `to`. All loads precede all stores, so `to` may be `from`.
template <class V>
inline void advancePack(const StepArgs& args, int j, int valid, const PathState& from, PathState* to, NodeLanes* out,
                        RootCounts* counts) {
  using T = LaneTraits<V>;
  using M = typename T::Mask;
  const Constants& k = *args.k;
  const StripConstants& sc = *args.strips;
  const Node& node = args.node;
  const double kInf = __builtin_inf();
  // Per-step terms: the same for all strips unless some come back from substeps.
  const StepTermLanes* ps = args.per_strip;
  const StepTerms& u = *args.uniform;
  const V g = ps ? T::load(ps->g + j) : V(u.g);
  const V m_over_g = ps ? T::load(ps->m_over_g + j) : V(u.m_over_g);
  const V dx = ps ? T::load(ps->dx + j) : V(u.dx);
  const V dy = ps ? T::load(ps->dy + j) : V(u.dy);
  const V inv_dx = ps ? T::load(ps->inv_dx + j) : V(u.inv_dx);
  const V inv_dy = ps ? T::load(ps->inv_dy + j) : V(u.inv_dy);
  const V w = ps ? T::load(ps->w + j) : V(u.w);
  const V a1 = ps ? T::load(ps->a1 + j) : V(u.c.a1);
  const V a2 = ps ? T::load(ps->a2 + j) : V(u.c.a2);
  const M real = T::firstLanes(valid);

  // History terms, pressure and the static limit.
  const V y = T::load(sc.y + j);
  const V p = V(node.px) * T::load(sc.gy + j);
  const V sat = select(p > V(k.p_0), V(node.sat_x) * T::load(sc.sat_y + j), V(k.sat_floor));
  const V sat_p = sat * p;  // sat(p) p [Pa]
  const V tau_static = V(k.mu_0) * sat_p;
  const V e_dlx = T::load(from.dlx + j), e_dly = T::load(from.dly + j);
  const V e_ux = T::load(from.ux + j), e_uy = T::load(from.uy + j);
  const V e_z = T::load(from.z + j), e_z_p = T::load(from.z_p + j);
  const M e_sliding = T::load(from.sliding + j) != V(0.0), e_sliding_p = T::load(from.sliding_p + j) != V(0.0);
  const V dhx = a1 * e_dlx + a2 * T::load(from.dlx_p + j);  // BDF2 history of delta [m]
  const V dhy = a1 * e_dly + a2 * T::load(from.dly_p + j);
  const V uhx = a1 * e_ux + a2 * T::load(from.ux_p + j), uhy = a1 * e_uy + a2 * T::load(from.uy_p + j);
  const V bx = m_over_g * uhx - V(k.kx) * dhx;  // history terms of the implicit update [Pa]
  const V by = m_over_g * uhy - V(k.ky) * dhy;
  // The current node becomes the previous one; stored now (all loads of `from` are done) so that these
  // values need not be kept across the root iteration's calls, which clobber every vector register.
  T::store(to->dlx_p + j, e_dlx);
  T::store(to->dly_p + j, e_dly);
  T::store(to->ux_p + j, e_ux);
  T::store(to->uy_p + j, e_uy);
  T::store(to->sliding_p + j, select(e_sliding, V(1.0), V(0.0)));
  T::store(to->z_p + j, e_z);
  V ndx = dhx + g * e_ux;  // deflection at the new node: predictor for the Omega delta coupling [m]
  V ndy = dhy + g * e_uy;
  V tx(0.0), ty(0.0), vsx(0.0), vsy(0.0), s(0.0), mup(0.0), s_dmup(0.0), z(0.0), nux(0.0), nuy(0.0);
  M stuck = T::none();

  for (int pass = 0; pass < k.passes; ++pass) {
    // Trial stress (the stress needed to stick) and the stick test.
    const V rx = V(k.vrx0) + V(k.omega) * (y + ndy), ry = V(k.vry0) - V(k.omega) * (V(node.x) + ndx);
    const V ttx = dx * rx - bx, tty = dy * ry - by;
    const V t2x = ttx * ttx, t2y = tty * tty, t2 = t2x + t2y;
    stuck = t2 <= tau_static * tau_static;

    // Slide root: F(z) = sum_i t_i^2 / (D_i s + mu(s) p)^2 - 1 = 0 in z = ln s, s = |v_s|, monotone
    // decreasing while D_i + p dmu/ds > 0. Newton in z on ln(F + 1), safeguarded by bisection on the
    // bracket [z_floor, ln(|t| / min D)], whose upper end is computed only when bisection needs it.
    // Creep test at the floor speed: there D s is negligible against mu p and mu = mu(floor).
    const V mup_floor = sat_p * V(k.savkoor_floor);
    const M creep = t2 <= mup_floor * mup_floor;
    M solving = real & !stuck & !creep;
    V root_s(0.0), root_z(0.0), root_mup(0.0), root_s_dmup(0.0), iterations(0.0);
    V z_lo(k.z_floor), z_hi(kInf);
    auto upperEnd = [&](const M& lanes) {
      const M need = lanes & (z_hi == V(kInf));
      if (any(need)) z_hi = select(need, vlog(select(need, vsqrt(t2) / vmin(dx, dy), V(1.0))), z_hi);
    };
    // Warm start: the previous pass at this node, else ln|v_s| extrapolated along the element path.
    const M have_guess = (s > V(0.0)) | e_sliding;
    V zi = select(s > V(0.0), z, select(e_sliding_p, e_z + w * (e_z - e_z_p), e_z));
    const M rising_start = solving & ((!have_guess) | (zi < V(k.ln_vm)));
    if (any(rising_start)) {
      // Closed-form creep root mu(s) p = |t| with D s neglected, on the rising branch (s < v_m): there it
      // is a better start than the warm start; beyond the peak of mu the warm start is.
      const V r = vsqrt(t2);
      const V e = (r / sat_p - V(k.mu_0)) / V(k.dmu);
      const M closed = rising_start & (e > V(0.0)) & (e < V(1.0));
      if (any(closed)) zi = select(closed, V(k.ln_vm) - vsqrt(-vlog(select(closed, e, V(1.0))) / V(k.savkoor_c)), zi);
      // Viscous estimate: D s carries what friction at its floor mu_0 p does not.
      const M viscous = rising_start & !closed & !have_guess;
      if (any(viscous)) {
        const V s_visc = vsqrt(t2x / (dx * dx) + t2y / (dy * dy));
        const V estimate = vmax(s_visc * (V(1.0) - sat_p * V(k.mu_0) / r), V(1e-300));
        zi = select(viscous, vlog(select(viscous, estimate, V(1.0))), zi);
      }
    }
    {
      const M outside = solving & !((zi > z_lo) & (zi < z_hi));
      if (any(outside)) {
        upperEnd(outside);
        zi = select(outside, V(0.5) * (z_lo + z_hi), zi);
      }
    }
    zi = select(solving, zi, V(0.0));  // lanes not solving evaluate a harmless residual

    // mu p and |v_s| d(mu p)/d|v_s| at z = ln|v_s| (Eq 10 times sat(p) p).
    auto friction = [&](const V& zv, V* mup_at, V* s_dmup_at) {
      const V l = zv - V(k.ln_vm);
      const V e = V(k.dmu) * vexp(V(-k.savkoor_c) * l * l);
      *mup_at = sat_p * (V(k.mu_0) + e);
      *s_dmup_at = sat_p * e * (V(-2.0 * k.savkoor_c) * l);
    };
    while (any(solving)) {
      // Residual F and dF/dz at zi.
      const V rs = vexp(zi);
      V rmup, rs_dmup;
      friction(zi, &rmup, &rs_dmup);
      const V gx = dx * rs + rmup, gy = dy * rs + rmup;
      const V inv = V(1.0) / (gx * gy);  // one division for both reciprocals
      const V igx = gy * inv, igy = gx * inv;
      const V fx = t2x * igx * igx, fy = t2y * igy * igy;
      const V dfdz = V(-2.0) * (fx * (dx * rs + rs_dmup) * igx + fy * (dy * rs + rs_dmup) * igy);
      const V f = fx + fy - V(1.0);

      // Safeguarded Newton step.
      iterations = select(solving, iterations + V(1.0), iterations);
      const M above = f > V(0.0);
      z_lo = select(solving & above, zi, z_lo);
      z_hi = select(solving & !above, zi, z_hi);
      // Far from the root F + 1 behaves like a power of s (like s^-2 where D s dominates), so Newton
      // on ln(F + 1) is nearly linear in z there; near the root both forms agree to O(F^2).
      const M descending = dfdz < V(0.0);
      const M far = solving & descending & !(vabs(f) < V(0.25));
      V numerator = -f;
      if (any(far)) numerator = select(far, -(V(1.0) + f) * vlog1p(select(far, f, V(0.0))), numerator);
      const V step = select(descending, numerator / dfdz, V(0.0));
      // Quadratic convergence: the remaining error is O(step^2); correct s and mu p to first order.
      const M converged = solving & descending & (vabs(step) < V(k.tol));
      root_z = select(converged, zi + step, root_z);
      root_s = select(converged, rs * (V(1.0) + step), root_s);
      root_mup = select(converged, rmup + rs_dmup * step, root_mup);
      root_s_dmup = select(converged, rs_dmup, root_s_dmup);
      solving = solving & !converged;
      V z_new = zi + step;
      const M bisect = solving & ((!descending) | (!((z_new > z_lo) & (z_new < z_hi))));
      if (any(bisect)) {
        upperEnd(bisect);
        z_new = select(bisect, V(0.5) * (z_lo + z_hi), z_new);
      }
      const M exhausted = solving & ((z_hi - z_lo < V(k.tol)) | (iterations == V(k.max_iterations)));
      if (any(exhausted)) {
        const V ze = select(exhausted, z_new, V(0.0));
        V mup_e, s_dmup_e;
        friction(ze, &mup_e, &s_dmup_e);
        root_z = select(exhausted, ze, root_z);
        root_s = select(exhausted, vexp(ze), root_s);
        root_mup = select(exhausted, mup_e, root_mup);
        root_s_dmup = select(exhausted, s_dmup_e, root_s_dmup);
        solving = solving & !exhausted;
      }
      zi = select(solving, z_new, zi);
    }

    // Node solution: stick, slide at the root, or creep at the static limit along the trial direction.
    const M slid = real & !stuck;
    const int pack_max_iterations = T::maxLane(select(slid, iterations, V(0.0)));
    if (pack_max_iterations > counts->max_iterations) counts->max_iterations = pack_max_iterations;
    counts->total += T::sumLanes(select(slid, iterations, V(0.0)));
    const M sliding = slid & (root_s > V(0.0));
    const M creeping = slid & !(root_s > V(0.0));
    {
      const V gx = dx * root_s + root_mup, gy = dy * root_s + root_mup;
      const V inv = V(1.0) / select(sliding, gx * gy, V(1.0));
      const V igx = gy * inv, igy = gx * inv;
      tx = select(stuck, ttx, root_mup * ttx * igx);
      ty = select(stuck, tty, root_mup * tty * igy);
      if (any(creeping)) {
        const V static_over_tt = tau_static / select(creeping, vsqrt(t2), V(1.0));
        tx = select(creeping, static_over_tt * ttx, tx);
        ty = select(creeping, static_over_tt * tty, ty);
      }
      vsx = select(sliding, -ttx * root_s * igx, V(0.0));
      vsy = select(sliding, -tty * root_s * igy, V(0.0));
    }
    s = select(stuck, V(0.0), root_s);
    z = select(sliding, root_z, V(0.0));
    mup = select(sliding, root_mup, mup);
    s_dmup = select(sliding, root_s_dmup, s_dmup);
    nux = (tx + bx) * inv_dx;
    nuy = (ty + by) * inv_dy;
    ndx = dhx + g * nux;
    ndy = dhy + g * nuy;
  }

  // Element state at the new node.
  T::store(to->dlx + j, ndx);
  T::store(to->dly + j, ndy);
  T::store(to->ux + j, nux);
  T::store(to->uy + j, nuy);
  T::store(to->sliding + j, select(s > V(0.0), V(1.0), V(0.0)));
  T::store(to->z + j, z);

  // Eq 19 per time; at the slide root |tau| = mu p exactly, and ln|v_s| = z is known. Below z_wear_cut
  // the sliding term is under 1e-9 w4 (deep creep) and is skipped.
  V wt(k.w4);
  const M wearing = (s > V(0.0)) & (z > V(k.z_wear_cut));
  if (any(wearing)) {
    const V sliding_wear = vexp(V(k.ln_w3_over_mpa_w1) + V(k.w1) * vlog(select(wearing, mup, V(1.0))) + V(k.w2) * z);
    wt = select(wearing, V(k.w4) + sliding_wear, wt);
  }
  V refine_rate(0.0);
  if (k.refine) {
    const M fast = real & (s > V(k.v_m));
    if (any(fast)) {
      const V s_fast = select(fast, s, V(1.0));
      const V inv_s2 = V(1.0) / (s_fast * s_fast);
      const V nx2 = vsx * vsx * inv_s2, ny2 = V(1.0) - nx2;  // squared slip direction
      const V k_dir = V(k.kx) * nx2 + V(k.ky) * ny2;
      const V c_eff = V(k.cx) * nx2 + V(k.cy) * ny2 + s_dmup * s_fast * inv_s2;
      const V c_crit = V(2.0) * vsqrt(V(k.m) * k_dir);
      const M weakly_damped = fast & !(c_eff >= V(k.damping_ratio) * c_crit);
      if (any(weakly_damped)) {
        const V inv_m(1.0 / k.m);
        refine_rate = select(weakly_damped, vmax(vsqrt(k_dir * inv_m), -c_eff * inv_m), refine_rate);
      }
    }
  }
  if (args.sums) {
    PatchSums& sum = *args.sums;
    const V area = V(args.node_area) * T::load(sc.weight + j);  // dA [m^2]
    const V zero(0.0);
    // Lanes past the last strip add nothing.
    const V force_x = select(real, area * tx, zero), force_y = select(real, area * ty, zero);
    T::store(sum.fx, T::load(sum.fx) + force_x);
    T::store(sum.fy, T::load(sum.fy) + force_y);
    T::store(sum.mz, T::load(sum.mz) + (V(node.x) * force_y - T::load(sc.y_mz + j) * force_x));
    T::store(sum.wear, T::load(sum.wear) + select(real, area * wt, zero));
    T::store(sum.stick, T::load(sum.stick) + select(real & (s <= V(k.v_m)), area, zero));
    T::store(sum.exact, T::load(sum.exact) + select(real & stuck, area, zero));
  }
  T::store(out->refine_rate + j, refine_rate);
  T::store(out->p + j, p);
  T::store(out->tx + j, tx);
  T::store(out->ty + j, ty);
  T::store(out->vsx + j, vsx);
  T::store(out->vsy + j, vsy);
  T::store(out->s + j, s);
  T::store(out->z + j, z);
  T::store(out->mup + j, mup);
  T::store(out->s_dmup + j, s_dmup);
  T::store(out->wt + j, wt);
  T::store(out->stuck + j, select(stuck, V(1.0), V(0.0)));
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
