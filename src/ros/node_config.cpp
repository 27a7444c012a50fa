#include "tread_wear/ros/node_config.h"

namespace tread_wear {

ConfigValue parameterTree(XmlRpc::XmlRpcValue& value) {
  ConfigValue v;
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeInvalid: break;
    case XmlRpc::XmlRpcValue::TypeBoolean:
      v.type = ConfigValue::Type::kBool;
      v.boolean = static_cast<bool>(value);
      break;
    case XmlRpc::XmlRpcValue::TypeInt:
      v.type = ConfigValue::Type::kNumber;
      v.number = static_cast<int>(value);
      break;
    case XmlRpc::XmlRpcValue::TypeDouble:
      v.type = ConfigValue::Type::kNumber;
      v.number = static_cast<double>(value);
      break;
    case XmlRpc::XmlRpcValue::TypeString:
      v.type = ConfigValue::Type::kString;
      v.string = static_cast<std::string>(value);
      break;
    case XmlRpc::XmlRpcValue::TypeArray:
      v.type = ConfigValue::Type::kList;
      for (int i = 0; i < value.size(); ++i) v.list.push_back(parameterTree(value[i]));
      break;
    case XmlRpc::XmlRpcValue::TypeStruct:
      v.type = ConfigValue::Type::kMap;
      for (auto& kv : value) v.map[kv.first] = parameterTree(kv.second);
      break;
    default:
      v.type = ConfigValue::Type::kString;
      v.string = value.toXml();
      break;
  }
  return v;
}

std::vector<geometry_msgs::TransformStamped> wheelFrameTransforms(const NodeConfig& config, const ros::Time& stamp) {
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (const WheelConfig& w : config.wheels) {
    if (!w.has_position) continue;
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = config.base_frame;
    t.child_frame_id = w.frame_id;
    t.transform.translation.x = w.position_m[0];
    t.transform.translation.y = w.position_m[1];
    t.transform.translation.z = w.position_m[2];
    t.transform.rotation.w = 1.0;
    transforms.push_back(t);
  }
  return transforms;
}

ConfigValue privateNamespaceTree(const ros::NodeHandle& pnh) {
  XmlRpc::XmlRpcValue namespace_tree;
  ConfigValue document;
  document.type = ConfigValue::Type::kMap;
  if (pnh.getParam(pnh.getNamespace(), namespace_tree) &&
      namespace_tree.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    document = parameterTree(namespace_tree);
  return document;
}

bool loadNodeConfig(const ros::NodeHandle& pnh, NodeConfig* config, std::string* error) {
  // An empty namespace reports `wheels` missing.
  return readNodeConfig(privateNamespaceTree(pnh), "", config, error);
}

}  // namespace tread_wear
