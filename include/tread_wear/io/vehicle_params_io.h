#pragma once
/// @file vehicle_params_io.h
/// Vehicle parameter files (config/vehicle_*.yaml) for the vehicle model (vehicle/vehicle_model.h).

#include <string>

#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

/// Loads config/vehicle_*.yaml (keys as the members, units in the names). @throw std::runtime_error
/// naming the file, the key and the problem; unknown keys are errors.
VehicleParams loadVehicleParams(const std::string& path);

}  // namespace tread_wear
