#include "tread_wear/ros/vehicle_inputs_config.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include "tread_wear/io/vehicle_inputs_config.h"
#include "tread_wear/ros/node_config.h"

namespace tread_wear {

bool loadVehicleInputsConfig(const ros::NodeHandle& pnh, VehicleInputsConfig* config, std::string* error) {
  XmlRpc::XmlRpcValue namespace_tree;
  // An empty private namespace is no map at all: then every key is absent (vehicle_params_file is reported missing).
  ConfigValue document;
  document.type = ConfigValue::Type::kMap;
  if (pnh.getParam(pnh.getNamespace(), namespace_tree) &&
      namespace_tree.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    document = parameterTree(namespace_tree);
  return readVehicleInputsConfig(document, config, error);
}

}  // namespace tread_wear
