#include "tread_wear/reference/solver_errors.h"

#include <algorithm>
#include <cmath>

namespace tread_wear {

void SolverErrors::maxWith(const SolverErrors& e) {
  fx = std::max(fx, e.fx);
  fy = std::max(fy, e.fy);
  mz = std::max(mz, e.mz);
  wear = std::max(wear, e.wear);
  stick = std::max(stick, e.stick);
  slide = std::max(slide, e.slide);
  exact_stick = std::max(exact_stick, e.exact_stick);
}

SolverErrors solverErrors(const WearResult& reference, const WearResult& result, double load_n) {
  const WearResult& r0 = reference;
  const double f_floor = std::max(0.05 * std::hypot(r0.fx_n, r0.fy_n), 0.005 * load_n);
  SolverErrors e;
  e.fx = std::fabs(result.fx_n - r0.fx_n) / std::max(std::fabs(r0.fx_n), f_floor);
  e.fy = std::fabs(result.fy_n - r0.fy_n) / std::max(std::fabs(r0.fy_n), f_floor);
  e.mz = std::fabs(result.mz_nm - r0.mz_nm) / std::max(std::fabs(r0.mz_nm), r0.half_length_m * f_floor);
  e.wear = std::fabs(result.wear_rate_kg_per_m / r0.wear_rate_kg_per_m - 1.0);
  e.stick = std::fabs(result.stick_fraction - r0.stick_fraction);
  e.slide = std::fabs(result.slide_fraction - r0.slide_fraction);
  e.exact_stick = std::fabs(result.exact_stick_fraction - r0.exact_stick_fraction);
  return e;
}

}  // namespace tread_wear
