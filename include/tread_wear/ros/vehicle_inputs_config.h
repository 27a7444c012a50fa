#pragma once
/// @file vehicle_inputs_config.h
/// vehicle_inputs_node's side of the front end's configuration (io/vehicle_inputs_config.h): the node's private
/// namespace on the parameter server (loaded from config/vehicle_inputs.yaml by the launch file) read as one document
/// and handed to the same reader, defaults and validation as tread_wear_vehicle_inputs's file. Every key and its
/// unit: docs/vehicle_inputs_node.md.

#include <ros/node_handle.h>

#include <string>

#include "tread_wear/estimation/vehicle_input_pipeline.h"

namespace tread_wear {

/// Reads the private namespace (defaults for absent keys; the vehicle from vehicle_params_file) and validates.
/// false with *error naming the key (a value of the wrong type, an unreadable vehicle file, validate()).
bool loadVehicleInputsConfig(const ros::NodeHandle& pnh, VehicleInputsConfig* config, std::string* error);

}  // namespace tread_wear
