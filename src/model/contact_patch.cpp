#include "tread_wear/model/contact_patch.h"

#include <algorithm>
#include <cmath>

namespace tread_wear {

PressureShape::PressureShape(double n, double lambda, double centre_ratio) : n_(n), lambda_(lambda) {
  A_ = (2.0 * n + 1.0) * (4.0 * n + 1.0) / (2.0 * n * (4.0 * n + 1.0 + lambda));
  B_ = -3.0 * (2.0 * n + 3.0) * (4.0 * n + 3.0) * (4.0 * n + 1.0 + lambda) /
       ((2.0 * n + 1.0) * (4.0 * n + 1.0) * (4.0 * n + 3.0 + 3.0 * lambda)) * centre_ratio;
}

double PressureShape::even(double s) const {
  const double t = std::pow(std::fabs(s), 2.0 * n_);
  return A_ * (1.0 - t) * (1.0 + lambda_ * t);
}

double PressureShape::operator()(double s) const {
  if (s < -1.0 || s > 1.0) return 0.0;
  return std::max(0.0, even(s) * (1.0 - B_ * s));
}

ContactPatch::ContactPatch(const FootprintParams& params, double load_n)
    : load_n_(load_n),
      a_m_(params.halfLength(load_n)),
      b_m_(params.b_m),
      gx_(params.n_x, params.lambda_x, params.x_e_m / a_m_),
      gy_(params.n_y, params.lambda_y, params.y_e_m / params.b_m) {}

double ContactPatch::lineLoad(double x_m) const { return load_n_ / (2.0 * a_m_) * gx_(x_m / a_m_); }

double ContactPatch::pressure(double x_m, double y_m) const {
  return lineLoad(x_m) / (2.0 * b_m_) * gy_(y_m / b_m_);
}

}  // namespace tread_wear
