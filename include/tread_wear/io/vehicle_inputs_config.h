#pragma once
/// @file vehicle_inputs_config.h
/// The front end's configuration (config/vehicle_inputs.yaml, estimation/vehicle_input_pipeline.h) read once for both
/// of its drivers: vehicle_inputs_node hands the parameter server's tree of its private namespace (the launch file
/// loads the YAML there; src/ros/vehicle_inputs_config.cpp), tread_wear_vehicle_inputs the same YAML file
/// (loadVehicleInputsConfigFile). Both go through readVehicleInputsConfig(), so a key, its default and its
/// constraint cannot differ between the node and the tool. ROS-free.

#include <string>

#include "tread_wear/estimation/vehicle_input_pipeline.h"
#include "tread_wear/io/wheel_config.h"

namespace tread_wear {

/// Reads a document (a map of the keys of docs/vehicle_inputs_node.md; absent keys keep VehicleInputsConfig's
/// defaults, unknown keys are ignored) and the vehicle of its vehicle_params_file (required), then validates.
/// false with *error naming the key (a value of the wrong type, an unreadable vehicle file, validate()).
bool readVehicleInputsConfig(const ConfigValue& document, VehicleInputsConfig* config, std::string* error);

/// Reads a YAML file through readVehicleInputsConfig(); vehicle_params_file, when not empty, replaces the file's
/// (the launch file and the tool's --vehicle set it). @throw std::runtime_error "<path>: <what>"
VehicleInputsConfig loadVehicleInputsConfigFile(const std::string& path, const std::string& vehicle_params_file);

}  // namespace tread_wear
