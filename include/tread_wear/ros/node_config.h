#pragma once
/// @file node_config.h
/// The node's side of the wheel configuration (io/wheel_config.h): the node's private namespace on the
/// parameter server (loaded from config/*.yaml by the launch files) read as one document and handed to the same
/// reader, defaults and validation as the replay's file. Every key and its unit: docs/node.md.

#include <geometry_msgs/TransformStamped.h>
#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "tread_wear/io/wheel_config.h"

namespace tread_wear {

/// A parameter-server value as the tree readNodeConfig() reads (int and double are numbers; any XML-RPC type
/// without a counterpart, date or binary, becomes its XML text, a string that no numeric key accepts).
ConfigValue parameterTree(XmlRpc::XmlRpcValue& value);

/// A private NodeHandle's namespace as a tree; an empty namespace (no map on the server) is an empty map, so that
/// every key reads as absent.
ConfigValue privateNamespaceTree(const ros::NodeHandle& pnh);

/// Reads the configuration from a private NodeHandle's namespace; false with *error naming the key on a bad or
/// missing value. Relative tire_params start at the working directory unless config_dir is set.
bool loadNodeConfig(const ros::NodeHandle& pnh, NodeConfig* config, std::string* error);

/// The static transforms base_frame -> frame_id of the wheels with a configured position_m, stamped `stamp`.
std::vector<geometry_msgs::TransformStamped> wheelFrameTransforms(const NodeConfig& config, const ros::Time& stamp);

}  // namespace tread_wear
