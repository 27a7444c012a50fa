#include "tread_wear/core/friction.h"

#include <algorithm>
#include <cmath>

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

}  // namespace tread_wear
