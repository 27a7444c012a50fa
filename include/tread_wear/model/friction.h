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

#include <array>
#include <cmath>
#include <cstddef>

#include "tread_wear/model/tire_params.h"

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
  /// C = h^2/ln(10)^2 [-]: the bracket of Eq 10 is mu_0 + (mu_m - mu_0) exp(-C ln^2(v_s/v_m)).
  double savkoorC() const { return h2_over_ln10sq_; }
  /// Full coefficient mu(v_s, p) [-] (Eq 10).
  double coefficient(double v_s_mps, double p_pa) const { return saturation(p_pa) * savkoor(v_s_mps); }
  const FrictionParams& params() const { return params_; }

 private:
  FrictionParams params_;
  double h2_over_ln10sq_ = 0.0;  ///< h^2 / ln(10)^2, so that h^2 log10^2(r) = this * ln^2(r)
};

/// (1 - u)^-q [-], the factor of sat(p) (Eq 11) that a pressure centre shift contributes where p separates as
/// p = p_even (1 - B x/a) (Eq 9): the marcher needs it at every x node of every evaluation (|B| is 0.07-0.12 on
/// the Grosch wheel at 150-50 N). For |u| <= kSeriesLimit it sums the binomial series sum_k c_k u^k, c_0 = 1,
/// c_k = c_{k-1} (q + k - 1)/k, by Horner to as many terms as |u| needs: with q in [0, 1) every c_k <= 1, so
/// n terms leave less than |u|^n / (1 - |u|) relative, and terms() keeps that below 1e-17. No pow is called
/// (16-20 multiply-adds for |u| of 0.07-0.12). Beyond kSeriesLimit, std::pow. Requires u < 1.
class ShiftSaturation {
 public:
  static constexpr double kSeriesLimit = 0.25;
  static constexpr int kMaxTerms = 31;  ///< enough for |u| <= kSeriesLimit
  ShiftSaturation() : ShiftSaturation(0.0) {}
  explicit ShiftSaturation(double q);

  /// Series terms for every |u| <= max_abs_u [-]; 0 (std::pow) when max_abs_u > kSeriesLimit.
  int terms(double max_abs_u) const;
  /// (1 - u)^-q for |u| <= the max_abs_u that `terms` was chosen for.
  double operator()(double u, int terms) const {
    double out;
    (*this)(&u, 1, terms, &out);
    return out;
  }
  /// The same for u[0..count) into out[0..count): Horner for all of them side by side, so that the independent
  /// chains overlap (and vectorise) instead of running one after the other.
  void operator()(const double* u, int count, int terms, double* out) const {
    if (terms == 0) {
      for (int m = 0; m < count; ++m) out[m] = std::pow(1.0 - u[m], -q_);
      return;
    }
    for (int m = 0; m < count; ++m) out[m] = c_[terms - 1];
    for (int k = terms - 1; k-- > 0;)
      for (int m = 0; m < count; ++m) out[m] = out[m] * u[m] + c_[k];
  }

 private:
  double q_ = 0.0;
  std::array<double, kMaxTerms> c_{};  ///< binomial series coefficients of (1 - u)^-q
};

/// Stability margin of steady sliding at vertical load Fz [N] (model spec, "Numerics"):
///   min(c_x, c_y) / (sat(p) p max|d savkoor/d v_s|) at the peak pressure p of the patch [-].
/// Linearised about steady sliding, an element obeys m u'' + (c - sat p dmu/dv_s) u' + k u = 0 along the slip
/// direction; where the friction law weakens faster than the damper damps (margin < 1) steady sliding is
/// unstable, elements stick-slip at about sqrt(k/m) and the marcher's results depend on its x grid (no grid of
/// practical size resolves the cycles). sat(p) p grows with p and p with Fz, so the margin falls with load.
double slidingStabilityMargin(const TireParams& params, double load_n);

}  // namespace tread_wear
