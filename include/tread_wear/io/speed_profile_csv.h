#pragma once
/// @file speed_profile_csv.h
/// Reading a speed profile (vehicle/speed_profile.h) from its CSV file; the format is documented there.

#include <string>
#include <vector>

#include "tread_wear/vehicle/speed_profile.h"

namespace tread_wear {

/// Reads a speed profile CSV. @throw std::runtime_error naming the file, line and problem
SpeedProfile loadSpeedProfile(const std::string& path);

/// Parses "Low 0-589, Medium 590-1022, ..." (the text after "Phases:"). False with *error on bad syntax.
bool parsePhaseList(const std::string& text, std::vector<ProfilePhase>* phases, std::string* error);

}  // namespace tread_wear
