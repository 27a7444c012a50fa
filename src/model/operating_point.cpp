#include "tread_wear/model/operating_point.h"

#include <cmath>

#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {

bool OperatingPoint::validate(std::string* error) const {
  if (!std::isfinite(speed_mps) || speed_mps < 0.0)
    return failValidation(error, "speed_mps", speed_mps, "finite and >= 0");
  if (!std::isfinite(slip_angle_rad) || std::fabs(slip_angle_rad) >= 0.5 * units::kPi)
    return failValidation(error, "slip_angle_rad", slip_angle_rad, "finite with |alpha| < pi/2");
  if (!std::isfinite(slip_ratio) || slip_ratio <= -1.0)
    return failValidation(error, "slip_ratio", slip_ratio, "finite and > -1");
  if (!std::isfinite(path_curvature_per_m))
    return failValidation(error, "path_curvature_per_m", path_curvature_per_m, "finite");
  if (!std::isfinite(load_n) || load_n <= 0.0) return failValidation(error, "load_n", load_n, "finite and > 0");
  if (std::isinf(tread_temperature_c))
    return failValidation(error, "tread_temperature_c", tread_temperature_c, "finite or NaN (unknown)");
  return true;
}

}  // namespace tread_wear
