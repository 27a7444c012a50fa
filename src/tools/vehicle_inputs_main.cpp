// tread_wear_vehicle_inputs: the offline vehicle-inputs front end, sensor bag -> the wear node's per-wheel inputs.
// Usage and proof: docs/vehicle_inputs.md; logic in ros/bag/vehicle_inputs_cli.h.
#include <iostream>

#include "tread_wear/ros/bag/vehicle_inputs_cli.h"

int main(int argc, char** argv) {
  return tread_wear::runVehicleInputsCli(argc, argv, TREAD_WEAR_SHARE_DIR, std::cout, std::cerr);
}
