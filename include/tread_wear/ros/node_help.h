#pragma once
/// @file node_help.h
/// `tread_wear_node --help`: usage, parameters (from the configuration's own defaults table), topics and services.

#include <string>

namespace tread_wear {

std::string nodeHelp();

}  // namespace tread_wear
