#include "tread_wear/core/operating_point.h"

#include <sstream>

#include "tread_wear/core/units.h"

namespace tread_wear {

bool OperatingPoint::validate(std::string* error) const {
  auto fail = [error](const char* field, double value, const char* constraint) {
    if (error != nullptr) {
      std::ostringstream msg;
      msg.precision(10);
      msg << field << " = " << value << ": must be " << constraint;
      *error = msg.str();
    }
    return false;
  };
  if (!std::isfinite(speed_mps) || speed_mps < 0.0) return fail("speed_mps", speed_mps, "finite and >= 0");
  if (!std::isfinite(slip_angle_rad) || std::fabs(slip_angle_rad) >= 0.5 * units::kPi)
    return fail("slip_angle_rad", slip_angle_rad, "finite with |alpha| < pi/2");
  if (!std::isfinite(slip_ratio) || slip_ratio <= -1.0) return fail("slip_ratio", slip_ratio, "finite and > -1");
  if (!std::isfinite(path_curvature_per_m)) return fail("path_curvature_per_m", path_curvature_per_m, "finite");
  if (!std::isfinite(load_n) || load_n <= 0.0) return fail("load_n", load_n, "finite and > 0");
  if (std::isinf(tread_temperature_c))
    return fail("tread_temperature_c", tread_temperature_c, "finite or NaN (unknown)");
  return true;
}

}  // namespace tread_wear
