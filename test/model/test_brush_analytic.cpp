// Analytic limits of the brush model (model spec, "Analytic checks"), for BOTH solvers: the marcher
// (BrushWearModel, BDF2 + return mapping) and the reference solver (ReferenceBrushSolver, CVODE with
// stick/slide events). The pressure moments of Eq 9 are tested in test_contact_patch.cpp.
// Expected values are closed forms derived here, or (classic brush with the Table 4 pressure shape)
// an independent 1D quadrature of the closed-form brush; none comes from either solver.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/friction.h"
#include "tread_wear/model/units.h"
#include "tread_wear/reference/reference_solver.h"

namespace tread_wear {
namespace {

// Vanishing mass and damping. The damping term of pure stick, 4ab c v_r (relative size c V/(k a),
// up to 2e-5 here), is included in the closed forms; the momentum given to the elements at entry,
// 2b m V_r |v_r|, is below 1e-7 of the forces tested.
constexpr double kTinyMass = 1e-4;     // [kg/m^2], Table 4: 20
constexpr double kTinyDamping = 10.0;  // [Pa s/m], Table 4: 1.16e5 and 5.6e5

TireParams linearBrushParams() {
  // "Friction unbounded": mu_0 = mu_m = 1e6 sticks every element except within p < k|delta|/mu of the
  // trailing edge and the shoulders, where p grows by ~1e9 Pa/m: a band < 1e-9 m wide (< 1e-6 of 2a).
  TireParams p;
  p.friction.mu_0 = p.friction.mu_m = 1e6;
  p.friction.q = 0.0;
  p.tread.m_kg_per_m2 = kTinyMass;
  p.tread.c_x_pa_s_per_m = p.tread.c_y_pa_s_per_m = kTinyDamping;
  return p;
}

// The marcher at 1600 x 64 (x 128 for the classic brush, whose stick/slide boundary its midpoint
// strips resolve slowly). Its last node sits at x = -a where p = 0, so it slides with
// tau = 0 and drops tau(-a) times half the last step, (1 - beta)/n of x/a with edge_grading beta = 0.8:
// when tau is largest at the trailing edge (stick to the end, tau ~ a - x) that costs Fy, Fx a
// fraction 0.2/n and Mz 0.6/n. This is the marcher's known first-order edge error, added to its
// tolerances below where it applies.
constexpr int kMarcherSteps = 1600;
constexpr double kMarcherEdgeLossForce = 0.2 / kMarcherSteps;
constexpr double kMarcherEdgeLossMoment = 0.6 / kMarcherSteps;

BrushOptions marcherOptions(int nx = kMarcherSteps, int ny = 64) {
  BrushOptions o;
  o.grid.n_x_steps = nx;
  o.grid.n_strips = ny;
  return o;
}

OperatingPoint straight(double speed, double alpha, double kappa, double load) {
  OperatingPoint op;
  op.speed_mps = speed;
  op.slip_angle_rad = alpha;
  op.slip_ratio = kappa;
  op.load_n = load;
  return op;
}

struct Solvers {
  explicit Solvers(const TireParams& p, const BrushOptions& mo = marcherOptions(),
                   const ReferenceSolverOptions& ro = ReferenceSolverOptions())
      : marcher(p, mo), reference(p, ro) {}
  /// Runs check(result, name, is_marcher) for both solvers.
  void both(const OperatingPoint& op, const std::function<void(const WearResult&, const char*, bool)>& check) {
    WearResult r;
    marcher.evaluate(op, &r);
    check(r, "marcher", true);
    reference.evaluate(op, &r);
    check(r, "reference", false);
  }
  BrushWearModel marcher;
  ReferenceBrushSolver reference;
};

// In stick, delta = v_r t along the path, so tau is linear in x: the marcher's trapezoid sums and
// the reference's error-controlled path integrals are exact up to the edge bands (< 1e-6), the
// vanishing m and c (< 1e-6) and the solver tolerances (< 1e-7), plus the marcher's edge loss.
constexpr double kLinearBrushTol = 1e-5;

TEST(BrushAnalytic, LinearBrushSideForceAndAligningMoment) {
  const TireParams p = linearBrushParams();
  Solvers s(p);
  for (double alpha_deg : {1.0, 4.0, -3.0}) {
    const double alpha = alpha_deg * units::kDegree, load = 75.0;
    const double a = p.footprint.halfLength(load), b = p.footprint.b_m;
    const double ky = p.tread.k_y0_pa_per_m + p.tread.k_y1_pa_per_m_n * load;
    const double fy = -4.0 * a * a * b * ky * std::tan(alpha) -
                      4.0 * a * b * p.tread.c_y_pa_s_per_m * 2.0 * std::sin(alpha);
    const double mz = 4.0 / 3.0 * a * a * a * b * ky * std::tan(alpha);
    s.both(straight(2.0, alpha, 0.0, load), [&](const WearResult& r, const char* who, bool marcher) {
      EXPECT_NEAR(r.fy_n / fy, 1.0, kLinearBrushTol + (marcher ? kMarcherEdgeLossForce : 0.0))
          << who << " alpha " << alpha_deg;
      EXPECT_NEAR(r.mz_nm / mz, 1.0, kLinearBrushTol + (marcher ? kMarcherEdgeLossMoment : 0.0))
          << who << " alpha " << alpha_deg;
      EXPECT_NEAR(r.fx_n, 0.0, 1e-6 * std::fabs(fy)) << who;
      EXPECT_GT(r.exact_stick_fraction, 0.999) << who;
    });
  }
}

TEST(BrushAnalytic, LinearBrushLongitudinalForce) {
  const TireParams p = linearBrushParams();
  Solvers s(p);
  for (double kappa : {0.02, -0.05}) {
    const double load = 60.0;
    const double a = p.footprint.halfLength(load), b = p.footprint.b_m;
    const double kx = p.tread.phi * (p.tread.k_y0_pa_per_m + p.tread.k_y1_pa_per_m_n * load);
    const double fx = 4.0 * a * a * b * kx * kappa / (1.0 + kappa) +
                      4.0 * a * b * p.tread.c_x_pa_s_per_m * kappa * 3.0;  // V_x = V = 3 m/s
    s.both(straight(3.0, 0.0, kappa, load), [&](const WearResult& r, const char* who, bool marcher) {
      EXPECT_NEAR(r.fx_n / fx, 1.0, kLinearBrushTol + (marcher ? kMarcherEdgeLossForce : 0.0))
          << who << " kappa " << kappa;
      EXPECT_NEAR(r.fy_n, 0.0, 1e-6 * std::fabs(fx)) << who;
    });
  }
}

// Table 4 damping and mass in pure stick (friction unbounded). Per element, integral tau_y dt =
// m [u_y] + c_y [delta_y] + k_y integral delta_y dt with delta_y = v_ry t, so
//   Fy = -4 a^2 b k_y tan(alpha) - 4 a b c_y V sin(alpha) - 2 b m V_r V sin(alpha)
// where the last term (momentum given to elements entering at rest) vanishes when they enter at
// the road's velocity (the model spec's form). The catch-up at entry lasts sqrt(2 m |v_r| /
// (mu V_r dp/dx)) ~ 4e-8 s: ~1e-5 of the contact time. Tolerance 2e-5 (+ the marcher's edge loss).
// The marcher is checked in the spec's form only: with entry at rest and unbounded friction the catch-up
// is far shorter than its first step and it books about half of the momentum term (-1.3e-3 of Fy,
// not converging with n_x; docs/convergence.md). With finite friction the catch-up spans many steps.
TEST(BrushAnalytic, DampingAndInertiaInPureStick) {
  TireParams p = linearBrushParams();
  p.tread = TreadParams();  // Table 4 c_x, c_y, m
  const double alpha = 3.0 * units::kDegree, load = 75.0, V = 2.0;
  const double a = p.footprint.halfLength(load), b = p.footprint.b_m;
  const double ky = p.tread.k_y0_pa_per_m + p.tread.k_y1_pa_per_m_n * load;
  const double Vr = V * std::cos(alpha);
  const double stiffness_term = -4.0 * a * a * b * ky * std::tan(alpha);
  const double damping_term = -4.0 * a * b * p.tread.c_y_pa_s_per_m * V * std::sin(alpha);
  const double momentum_term = -2.0 * b * p.tread.m_kg_per_m2 * Vr * V * std::sin(alpha);
  ASSERT_GT(std::fabs(damping_term), 0.1 * std::fabs(stiffness_term));  // the check has teeth
  for (bool at_road_velocity : {false, true}) {
    BrushOptions mo = marcherOptions();
    mo.enter_at_road_velocity = at_road_velocity;
    ReferenceSolverOptions ro;
    ro.enter_at_road_velocity = at_road_velocity;
    Solvers s(p, mo, ro);
    const double fy = stiffness_term + damping_term + (at_road_velocity ? 0.0 : momentum_term);
    s.both(straight(V, alpha, 0.0, load), [&](const WearResult& r, const char* who, bool marcher) {
      if (marcher && !at_road_velocity) return;
      EXPECT_NEAR(r.fy_n / fy, 1.0, 2e-5 + (marcher ? kMarcherEdgeLossForce : 0.0))
          << who << " enter_at_road_velocity " << at_road_velocity;
    });
  }
}

// Small slip angle with the paper's friction law (Table 4 friction, vanishing m and c): the sliding
// zone at the trailing edge, where mu_0 sat p < k_y tan(alpha) 2a, is ~ k_y tan(alpha) 2a / (mu_0 sat dp/dx)
// long, so the cornering stiffness -Fy / tan(alpha) approaches 4 a^2 b k_y with an error ~ tan(alpha):
// about 2e-4 relative per 1e-3 rad. Checked at 1e-4 rad (tolerance 1e-4 + the marcher's edge loss),
// and the error must shrink from 2e-3 rad to 1e-4 rad.
TEST(BrushAnalytic, SmallSlipCorneringStiffnessWithPaperFriction) {
  TireParams p;
  p.tread.m_kg_per_m2 = kTinyMass;
  p.tread.c_x_pa_s_per_m = p.tread.c_y_pa_s_per_m = kTinyDamping;
  Solvers s(p);
  const double load = 75.0;
  const double a = p.footprint.halfLength(load), b = p.footprint.b_m;
  const double c0 = 4.0 * a * a * b * (p.tread.k_y0_pa_per_m + p.tread.k_y1_pa_per_m_n * load);
  double error_at[2] = {0.0, 0.0};
  int k = 0;
  for (double alpha : {2e-3, 1e-4}) {
    s.both(straight(2.0, alpha, 0.0, load), [&](const WearResult& r, const char* who, bool marcher) {
      const double err = std::fabs(-r.fy_n / std::tan(alpha) / c0 - 1.0);
      if (alpha < 1e-3) {
        EXPECT_LT(err, 1e-4 + (marcher ? kMarcherEdgeLossForce : 0.0)) << who;
      }
      error_at[k] = std::max(error_at[k], err);
    });
    ++k;
  }
  EXPECT_LT(error_at[1], error_at[0]);
}

// Large slip, Coulomb friction mu_0 = mu_m = 1 with q = 0: |F| <= Fz always, and once (nearly) every
// element slides |F|/Fz -> 1. The stick zone at the leading edge, where k tan(alpha) (a - x) < p,
// is ~ p_mean / (k tan(alpha)) long: at 88 deg about 3e-3 of the length, costing half of that.
TEST(BrushAnalytic, LargeSlipCoulombSaturatesAtFz) {
  TireParams p;
  p.friction.mu_0 = p.friction.mu_m = 1.0;
  p.friction.q = 0.0;
  Solvers s(p);
  for (double alpha_deg : {88.0, -88.0}) {
    const double load = 75.0;
    s.both(straight(2.0, alpha_deg * units::kDegree, 0.0, load), [&](const WearResult& r, const char* who, bool) {
      const double ratio = std::hypot(r.fx_n, r.fy_n) / load;
      EXPECT_LT(ratio, 1.0 + 1e-6) << who;
      EXPECT_GT(ratio, 1.0 - 3e-3) << who << " alpha " << alpha_deg;
      EXPECT_GT(-r.fy_n * alpha_deg, 0.0) << who;
    });
  }
}

// Large slip with the paper's friction law (Table 4): in full sliding v_s ~ V sin(alpha) everywhere,
// so |F|/Fz tends to the pressure-weighted average of sat(p) mu(V sin alpha), computed here by 2D
// Simpson quadrature. Deviation: the stick/creep zone at the leading edge (~3e-3 of the length at
// 88 deg) and |u| << V sin(alpha) in sliding (delta ~ tau/k changes over the patch): tolerance 5e-3.
TEST(BrushAnalytic, LargeSlipPaperFrictionTendsToSlidingAverage) {
  const TireParams p;
  Solvers s(p);
  const SavkoorFriction friction(p.friction);
  const double load = 75.0, V = 2.0, alpha = 88.0 * units::kDegree;
  const ContactPatch patch(p.footprint, load);
  const double a = patch.halfLength(), b = patch.halfWidth();
  const double savkoor = friction.savkoor(V * std::sin(alpha));
  const int n = 1000;
  double expected = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double wi = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    for (int j = 0; j <= n; ++j) {
      const double wj = (j == 0 || j == n) ? 1 : (j % 2 ? 4 : 2);
      const double pr = patch.pressure(-a + 2.0 * a * i / n, -b + 2.0 * b * j / n);
      expected += wi * wj * friction.saturation(pr) * savkoor * pr;
    }
  }
  expected *= (2.0 * a / n / 3.0) * (2.0 * b / n / 3.0) / load;
  s.both(straight(V, alpha, 0.0, load), [&](const WearResult& r, const char* who, bool) {
    EXPECT_NEAR(std::hypot(r.fx_n, r.fy_n) / load / expected, 1.0, 5e-3) << who;
  });
}

// Classic brush (m, c -> 0, Coulomb mu with q = 0, pure side slip): per lateral position y the element
// sticks with tau_y = -k_y tan(alpha) (a - x) until that reaches mu p(x, y) at x_s, then slides with
// tau_y = -mu p (sign of alpha). Closed form in the stick part, Simpson quadrature of mu p in the slide
// part, Simpson across y: an independent evaluation of the classic brush for the Table 4 pressure shape.
struct ClassicBrush {
  double fy = 0.0, mz = 0.0;
};

ClassicBrush classicBrush(const TireParams& p, double alpha, double load) {
  const ContactPatch patch(p.footprint, load);
  const double a = patch.halfLength(), b = patch.halfWidth(), mu = p.friction.mu_0;
  const double ky = p.tread.k_y0_pa_per_m + p.tread.k_y1_pa_per_m_n * load;
  const double t = std::fabs(std::tan(alpha)), sign = alpha > 0 ? 1.0 : -1.0;
  ClassicBrush out;
  const int ny = 400, nx = 2000;
  for (int j = 0; j <= ny; ++j) {
    const double y = -b + 2.0 * b * j / ny;
    const double wj = ((j == 0 || j == ny) ? 1 : (j % 2 ? 4 : 2)) * 2.0 * b / ny / 3.0;
    // x_s: the first x below a where k t (a - x) > mu p(x, y); the stick line starts at 0 with a
    // smaller slope than mu p, so bracket from just inside the leading edge.
    auto excess = [&](double x) { return ky * t * (a - x) - mu * patch.pressure(x, y); };
    double xs = -a;
    const int scan = 4000;
    for (int i = 1; i <= scan; ++i) {
      const double x = a - 2.0 * a * i / scan;
      if (excess(x) > 0.0) {
        double lo = x, hi = a - 2.0 * a * (i - 1) / scan;  // excess(lo) > 0 >= excess(hi)
        for (int it = 0; it < 100; ++it) {
          const double mid = 0.5 * (lo + hi);
          (excess(mid) > 0.0 ? lo : hi) = mid;
        }
        xs = 0.5 * (lo + hi);
        break;
      }
    }
    const double L = a - xs;
    double fy = -ky * t * L * L / 2.0;                                        // stick: integral (a - x)
    double mz = -ky * t * (a * (a * a - xs * xs) / 2.0 - (a * a * a - xs * xs * xs) / 3.0);  // integral x (a - x)
    if (xs > -a) {
      for (int i = 0; i <= nx; ++i) {
        const double x = -a + (xs + a) * i / nx;
        const double wi = ((i == 0 || i == nx) ? 1 : (i % 2 ? 4 : 2)) * (xs + a) / nx / 3.0;
        fy -= wi * mu * patch.pressure(x, y);
        mz -= wi * x * mu * patch.pressure(x, y);
      }
    }
    out.fy += sign * wj * fy;
    out.mz += sign * wj * mz;  // Mz = integral (x tau_y - y tau_x) dA with tau_x = 0
  }
  return out;
}

TEST(BrushAnalytic, VanishingMassAndDampingReproduceTheClassicBrush) {
  TireParams p;
  p.friction.mu_0 = p.friction.mu_m = 1.0;
  p.friction.q = 0.0;
  p.tread.m_kg_per_m2 = kTinyMass;
  p.tread.c_x_pa_s_per_m = p.tread.c_y_pa_s_per_m = kTinyDamping;
  Solvers s(p, marcherOptions(kMarcherSteps, 128));
  for (double alpha_deg : {2.0, 6.0}) {
    const double alpha = alpha_deg * units::kDegree, load = 75.0;
    const ClassicBrush expected = classicBrush(p, alpha, load);
    // The quadrature above (kink at a bisected x_s, Simpson on either side, 400 Simpson panels in y)
    // is accurate to ~1e-6; the reference locates the kink by its event; the marcher's midpoint strips
    // across the stick/slide boundary cost ~1e-4 (Fy) and ~2e-4 (Mz, a difference of larger terms) at
    // 64 strips, converging as 1/n_strips^2: 128 strips here. Tolerances: 1e-4 (Fy) and 3e-4 (Mz).
    s.both(straight(2.0, alpha, 0.0, load), [&](const WearResult& r, const char* who, bool) {
      EXPECT_NEAR(r.fy_n / expected.fy, 1.0, 1e-4) << who << " alpha " << alpha_deg;
      EXPECT_NEAR(r.mz_nm / expected.mz, 1.0, 3e-4) << who << " alpha " << alpha_deg;
    });
  }
}

}  // namespace
}  // namespace tread_wear
