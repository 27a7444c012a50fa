#pragma once
/// @file rolling_radius_store.h
/// Persistence of the learned effective rolling radii of vehicle_inputs_node (estimation/rolling_radius_learner.h),
/// so a restart keeps them. File: JSON `{"format": "tread_wear_rolling_radii", "version": 1, "saved_unix_s": ...,
/// "wheels": [{"name", "radius_m", "learned_distance_m"}]}`, written atomically (`<path>.tmp`, fsync, rename).
/// A missing file is a first start; an unparsable or invalid one is reported with the reason and left in place
/// (the caller starts from the nominal radii and does not overwrite it until the next successful save).
/// Not for a real-time loop: allocates and does blocking I/O.

#include <array>
#include <string>

#include "tread_wear/estimation/rolling_radius_learner.h"

namespace tread_wear {

enum class RadiusLoadStatus { kLoaded = 0, kMissing = 1, kInvalid = 2 };
const char* radiusLoadStatusName(RadiusLoadStatus status);

/// The document's text for the wheels `names` (same order as `state`).
std::string rollingRadiiJson(const std::array<std::string, kWheelCount>& names,
                             const std::array<RollingRadiusState, kWheelCount>& state, double saved_unix_s);
/// Parses the text; every wheel of `names` must be present with radius_m > 0 and learned_distance_m >= 0, finite.
/// false with *error naming the problem.
bool parseRollingRadiiJson(const std::string& text, const std::array<std::string, kWheelCount>& names,
                           std::array<RollingRadiusState, kWheelCount>* state, std::string* error);
/// Reads the file (kMissing when it does not exist; kInvalid with *error for an unreadable or bad file).
RadiusLoadStatus loadRollingRadii(const std::string& path, const std::array<std::string, kWheelCount>& names,
                                  std::array<RollingRadiusState, kWheelCount>* state, std::string* error);
/// Atomic write; false with *error naming the failed step.
bool saveRollingRadii(const std::string& path, const std::array<std::string, kWheelCount>& names,
                      const std::array<RollingRadiusState, kWheelCount>& state, double saved_unix_s,
                      std::string* error);

}  // namespace tread_wear
