#include "tread_wear/ros/node_config.h"

namespace tread_wear {

nlohmann::json parameterTree(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return static_cast<bool>(value);
    case XmlRpc::XmlRpcValue::TypeInt: return static_cast<int>(value);
    case XmlRpc::XmlRpcValue::TypeDouble: return static_cast<double>(value);
    case XmlRpc::XmlRpcValue::TypeString: return static_cast<std::string>(value);
    case XmlRpc::XmlRpcValue::TypeArray: {
      nlohmann::json list = nlohmann::json::array();
      for (int i = 0; i < value.size(); ++i) list.push_back(parameterTree(value[i]));
      return list;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      nlohmann::json map = nlohmann::json::object();
      for (auto& kv : value) map[kv.first] = parameterTree(kv.second);
      return map;
    }
    default: return value.toXml();
  }
}

bool loadNodeConfig(const ros::NodeHandle& pnh, NodeConfig* config, std::string* error) {
  XmlRpc::XmlRpcValue namespace_tree;
  // An empty private namespace is no map at all: then every key is absent (and `wheels` is reported missing).
  nlohmann::json document = nlohmann::json::object();
  if (pnh.getParam(pnh.getNamespace(), namespace_tree) &&
      namespace_tree.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    document = parameterTree(namespace_tree);
  return readNodeConfig(document, "", config, error);
}

}  // namespace tread_wear
