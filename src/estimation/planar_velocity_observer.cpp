#include "tread_wear/estimation/planar_velocity_observer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {
bool positive(double v) { return std::isfinite(v) && v > 0.0; }
}  // namespace

bool PlanarObserverParams::validate(std::string* error) const {
  if (!positive(accel_noise_mps2)) return failValidation(error, "accel_noise_mps2", accel_noise_mps2, "finite and > 0");
  if (!positive(offset_random_walk_mps2_per_sqrt_s))
    return failValidation(error, "offset_random_walk_mps2_per_sqrt_s", offset_random_walk_mps2_per_sqrt_s,
                          "finite and > 0");
  if (!positive(initial_velocity_sigma_mps))
    return failValidation(error, "initial_velocity_sigma_mps", initial_velocity_sigma_mps, "finite and > 0");
  if (!positive(initial_offset_sigma_mps2))
    return failValidation(error, "initial_offset_sigma_mps2", initial_offset_sigma_mps2, "finite and > 0");
  return true;
}

PlanarVelocityObserver::PlanarVelocityObserver(const PlanarObserverParams& params) : params_(params) {
  std::string error;
  if (!params_.validate(&error)) throw std::invalid_argument("invalid observer parameters: " + error);
  reset(0.0, 0.0);
}

void PlanarVelocityObserver::reset(double v_x_mps, double v_y_mps, double b_x_mps2, double b_y_mps2) {
  x_ << v_x_mps, v_y_mps, b_x_mps2, b_y_mps2;
  const double sv = params_.initial_velocity_sigma_mps, sb = params_.initial_offset_sigma_mps2;
  P_.setZero();
  P_.diagonal() << sv * sv, sv * sv, sb * sb, sb * sb;
}

void PlanarVelocityObserver::predict(double dt_s, double f_x_mps2, double f_y_mps2, double yaw_rate_rps) {
  if (!(dt_s > 0.0)) return;
  Covariance F = Covariance::Identity();
  F(kVx, kVy) = yaw_rate_rps * dt_s;
  F(kVy, kVx) = -yaw_rate_rps * dt_s;
  F(kVx, kBx) = -dt_s;
  F(kVy, kBy) = -dt_s;
  State next = F * x_;
  next(kVx) += f_x_mps2 * dt_s;
  next(kVy) += f_y_mps2 * dt_s;
  x_ = next;
  const double qa = params_.accel_noise_mps2 * params_.accel_noise_mps2 * dt_s;
  const double qb = params_.offset_random_walk_mps2_per_sqrt_s * params_.offset_random_walk_mps2_per_sqrt_s * dt_s;
  Covariance P = F * P_ * F.transpose();
  P(kVx, kVx) += qa;
  P(kVy, kVy) += qa;
  P(kBx, kBx) += qb;
  P(kBy, kBy) += qb;
  P_ = 0.5 * (P + P.transpose());
}

double PlanarVelocityObserver::update(const Row& h, double offset, double z, double variance, double gate) {
  const Row Ph = P_ * h;
  const double s = h.dot(Ph) + variance;
  if (!(s > 0.0) || !std::isfinite(z)) return -1.0;
  const double innovation = z - (h.dot(x_) + offset);
  const double nis = innovation * innovation / s;
  if (nis > gate) return -1.0;
  const Row k = Ph / s;
  x_ += k * innovation;
  // Joseph form keeps P symmetric positive semi-definite under rounding.
  const Covariance I_KH = Covariance::Identity() - k * h.transpose();
  P_ = I_KH * P_ * I_KH.transpose() + variance * k * k.transpose();
  return nis;
}

double PlanarVelocityObserver::sigma(Index i) const { return std::sqrt(std::max(0.0, P_(i, i))); }

}  // namespace tread_wear
