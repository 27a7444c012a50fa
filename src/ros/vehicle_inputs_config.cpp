#include "tread_wear/ros/vehicle_inputs_config.h"

#include "tread_wear/io/vehicle_inputs_config.h"
#include "tread_wear/ros/node_config.h"

namespace tread_wear {

bool loadVehicleInputsConfig(const ros::NodeHandle& pnh, VehicleInputsConfig* config, std::string* error) {
  // An empty namespace reports vehicle_params_file missing.
  return readVehicleInputsConfig(privateNamespaceTree(pnh), config, error);
}

}  // namespace tread_wear
