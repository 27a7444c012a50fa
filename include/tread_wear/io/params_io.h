#pragma once
/// @file params_io.h
/// Tire parameter files (YAML) with units in the keys, converted to SI once on load.
/// Format and accepted units: docs/parameters.md. Example: config/tires/grosch_wheel.yaml.

#include <stdexcept>
#include <string>

#include "tread_wear/model/tire_params.h"

namespace tread_wear {

/// Geometry of the Grip and Abrasion Test Stand (paper Table 1).
struct RigGeometry {
  double track_radius_m = 60e-3;  ///< R_t [m]
  double wheel_radius_m = 36e-3;  ///< Grosch wheel radius [m]
  double wheel_width_m = 18e-3;   ///< Grosch wheel width [m]
  double rim_radius_m = 30e-3;    ///< rim radius [m]

  bool validate(std::string* error) const;
};

/// Error in a parameter file: names the file, the key, the value and the broken constraint.
class ParamsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Loads and validates a tire parameter file. @throw ParamsError
TireParams loadTireParams(const std::string& path);
/// Loads the optional `rig` section of a parameter file (defaults when absent). @throw ParamsError
RigGeometry loadRigGeometry(const std::string& path);
/// Writes parameters in the same format (SI keys), so that a calibrated set can be loaded again.
void saveTireParams(const TireParams& params, const std::string& path, const std::string& comment = "");

}  // namespace tread_wear
