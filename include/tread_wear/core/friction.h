#pragma once
/// @file friction.h
/// Savkoor friction law with pressure saturation, paper Eqs 10-11.
///
///   mu(v_s, p) = sat(p) (mu_0 + (mu_m - mu_0) exp(-h^2 log10^2(v_s/v_m)))        (Eq 10)
///   sat(p)     = (max(p, p_0)/p_ref)^(-q)                                       (Eq 11)
///
/// mu rises from sat mu_0 at v_s = 0 to sat mu_m at v_s = v_m, then falls back towards sat mu_0.
/// Friction opposes slip (model spec: Eq 18 as printed has a sign slip).
/// Limits: no temperature, humidity or surface-state dependence (see the mismatch diagnosis library).

#include "tread_wear/core/tire_params.h"

namespace tread_wear {

class SavkoorFriction {
 public:
  SavkoorFriction() = default;
  explicit SavkoorFriction(const FrictionParams& params);

  /// sat(p) [-] for contact pressure p [Pa] (Eq 11).
  double saturation(double p_pa) const;
  /// Savkoor factor mu(v_s)/sat(p) [-] at sliding speed v_s [m/s] >= 0 (bracket of Eq 10).
  double savkoor(double v_s_mps) const;
  /// d(savkoor)/d v_s [s/m].
  double savkoorDerivative(double v_s_mps) const;
  /// Steepest velocity weakening max over v_s > v_m of -d(savkoor)/d v_s [s/m] (0 if mu_m <= mu_0 or h = 0).
  /// With C = h^2/ln(10)^2 and l = ln(v_s/v_m) it is reached at l* = (sqrt(1 + 8 C) - 1)/(4 C), where
  /// d/dl ln(l exp(-C l^2 - l)) = 0: (mu_m - mu_0) 2 C l* exp(-C l*^2) / (v_m exp(l*)).
  double maxWeakeningSlope() const;
  /// Full coefficient mu(v_s, p) [-] (Eq 10).
  double coefficient(double v_s_mps, double p_pa) const { return saturation(p_pa) * savkoor(v_s_mps); }
  const FrictionParams& params() const { return params_; }

 private:
  FrictionParams params_;
  double h2_over_ln10sq_ = 0.0;  ///< h^2 / ln(10)^2, so that h^2 log10^2(r) = this * ln^2(r)
};

/// Stability margin of steady sliding at vertical load Fz [N] (model spec, "Numerics"):
///   min(c_x, c_y) / (sat(p) p max|d savkoor/d v_s|) at the peak pressure p of the patch [-].
/// Linearised about steady sliding, an element obeys m u'' + (c - sat p dmu/dv_s) u' + k u = 0 along the slip
/// direction; where the friction law weakens faster than the damper damps (margin < 1) steady sliding is
/// unstable, elements stick-slip at about sqrt(k/m) and the marcher's results depend on its x grid (no grid of
/// practical size resolves the cycles). sat(p) p grows with p and p with Fz, so the margin falls with load.
double slidingStabilityMargin(const TireParams& params, double load_n);

}  // namespace tread_wear
