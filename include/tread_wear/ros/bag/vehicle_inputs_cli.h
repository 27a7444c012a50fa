#pragma once
/// @file vehicle_inputs_cli.h
/// tread_wear_vehicle_inputs IN.bag OUT.bag [--vehicle VEHICLE.yaml] [--rate-hz 100] [--wheel-radius 0.305]
///     [--steering-ratio 15]
/// The offline vehicle-inputs front end (vehicle_inputs_bag.h): sensor topics in, the wear node's per-wheel inputs
/// out; prints what it read and, for a bag that also holds the true inputs, the error table (docs/vehicle_inputs.md).
/// The default vehicle is `share_dir`/config/vehicle_passenger_car.yaml.
/// Returns 0, 1 for bad data (unreadable, corrupt or incomplete bag, bad vehicle file) or 2 for bad usage.

#include <ostream>
#include <string>

namespace tread_wear {

int runVehicleInputsCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out,
                        std::ostream& err);

}  // namespace tread_wear
