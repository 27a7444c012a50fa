#include "tread_wear/model/friction.h"

#include "tread_wear/model/contact_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tread_wear {

SavkoorFriction::SavkoorFriction(const FrictionParams& params) : params_(params) {
  const double ln10 = std::log(10.0);
  h2_over_ln10sq_ = params.h * params.h / (ln10 * ln10);
}

double SavkoorFriction::saturation(double p_pa) const {
  return std::pow(std::max(p_pa, params_.p_0_pa) / params_.p_ref_pa, -params_.q);
}

double SavkoorFriction::savkoor(double v_s_mps) const {
  if (!(v_s_mps > 0.0)) return params_.mu_0;
  const double l = std::log(v_s_mps / params_.v_m_mps);
  return params_.mu_0 + (params_.mu_m - params_.mu_0) * std::exp(-h2_over_ln10sq_ * l * l);
}

double SavkoorFriction::savkoorDerivative(double v_s_mps) const {
  if (!(v_s_mps > 0.0)) return 0.0;  // exp(-c ln^2) decays faster than any power of v_s
  const double l = std::log(v_s_mps / params_.v_m_mps);
  return (params_.mu_m - params_.mu_0) * std::exp(-h2_over_ln10sq_ * l * l) * (-2.0 * h2_over_ln10sq_ * l) / v_s_mps;
}

double SavkoorFriction::maxWeakeningSlope() const {
  const double drop = params_.mu_m - params_.mu_0;
  const double c = h2_over_ln10sq_;
  if (!(drop > 0.0) || !(c > 0.0)) return 0.0;
  const double l = (std::sqrt(1.0 + 8.0 * c) - 1.0) / (4.0 * c);
  return drop * 2.0 * c * l * std::exp(-c * l * l) / (params_.v_m_mps * std::exp(l));
}

double slidingStabilityMargin(const TireParams& params, double load_n) {
  // Peak pressure: p(x, y) = f_z(x)/(2b) g_y(y/b) separates, so its maximum is the product of the two maxima,
  // found on a fine sampling of each shape (the shapes are smooth and have one interior maximum).
  const ContactPatch patch(params.footprint, load_n);
  constexpr int kSamples = 4000;
  double line_max = 0.0, gy_max = 0.0;
  for (int i = 0; i <= kSamples; ++i) {
    const double s = -1.0 + 2.0 * i / kSamples;
    line_max = std::max(line_max, patch.lineLoad(s * patch.halfLength()));
    gy_max = std::max(gy_max, patch.shapeY()(s));
  }
  const double p_peak = line_max / (2.0 * patch.halfWidth()) * gy_max;
  const SavkoorFriction friction(params.friction);
  const double weakening = friction.saturation(p_peak) * p_peak * friction.maxWeakeningSlope();
  const double damping = std::min(params.tread.c_x_pa_s_per_m, params.tread.c_y_pa_s_per_m);
  return weakening > 0.0 ? damping / weakening : std::numeric_limits<double>::infinity();
}

ShiftSaturation::ShiftSaturation(double q) : q_(q) {
  c_[0] = 1.0;
  for (int k = 1; k < kMaxTerms; ++k) c_[k] = c_[k - 1] * (q + k - 1.0) / k;
}

int ShiftSaturation::terms(double max_abs_u) const {
  constexpr double kTruncation = 1e-17;  // relative, below a double's rounding
  if (!(max_abs_u <= kSeriesLimit)) return 0;
  if (max_abs_u == 0.0) return 1;
  // Smallest n with max_abs_u^n / (1 - max_abs_u) <= kTruncation (kMaxTerms covers kSeriesLimit).
  const double n = std::ceil(std::log(kTruncation * (1.0 - max_abs_u)) / std::log(max_abs_u));
  return std::min(kMaxTerms, std::max(1, static_cast<int>(n)));
}

}  // namespace tread_wear
